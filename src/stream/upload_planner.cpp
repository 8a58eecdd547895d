#include "ridge/stream/upload_planner.h"

#include "ridge/core/error.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <cmath>

namespace ridge::stream {

namespace {

// Err_Scr is capped below one level's rank, so that a huge error never outranks a coarser
// level (coarse before fine is what makes GPU reconstruction and the fallback work).
constexpr double kLevelRank = 1e6;

const PatchId kRoot{0, 0, 0};

} // namespace

double requestPriority(const PyramidGeometry& geometry, PatchId p, double rank)
{
    return kLevelRank * (geometry.levelCount() - p.level) + std::clamp(rank, 0.0, kLevelRank - 1.0);
}

double detailPriority(const PyramidGeometry& geometry, PatchId p, double rank)
{
    // requestPriority lies in [10^6, (levels + 1)·10^6): scaled into [0, 10^6), below every
    // drawn patch's and above every prefetch's, coarse first still.
    return requestPriority(geometry, p, rank) / double(geometry.levelCount() + 1);
}

double prefetchPriority(const PyramidGeometry& geometry, PatchId p, double rank)
{
    // The finest level ranks 10^6 in requestPriority, the root (levels + 1)·10^6 at most.
    return requestPriority(geometry, p, rank) - kLevelRank * (geometry.levelCount() + 1);
}

std::optional<lod::Camera> extrapolatedCamera(const lod::Camera& camera, glm::dvec3 velocity,
                                              int frames)
{
    if (frames <= 0 || !(glm::length(velocity) > 0.0))
        return std::nullopt;
    // Within the coordinates a camera may take, however far a jump extrapolates.
    const double limit = lod::kCameraCoordinateRange.hi;
    const glm::dvec3 ahead = glm::clamp(camera.position() + velocity * double(frames),
                                        glm::dvec3(-limit), glm::dvec3(limit));
    return lod::Camera(ahead, ahead + camera.forward(), glm::degrees(camera.fovY()),
                       camera.viewport(), camera.nearPlane(), camera.farPlane());
}

UploadTimeBudget::UploadTimeBudget(const UploadTimeSettings& settings) : settings_(settings)
{
    checkParameter("upload_budget_ms", settings.floor_ms, UploadTimeSettings::kFloorMsRange);
    checkParameter("upload_frame_fraction", settings.frame_fraction,
                   UploadTimeSettings::kFrameFractionRange);
    checkParameter("upload_budget_max_ms", settings.ceiling_ms,
                   UploadTimeSettings::kCeilingMsRange);
    budget_ms_ = settings.floor_ms;
}

double UploadTimeBudget::beginFrame(double now_ms)
{
    // The previous frame's own work: its interval less its uploads (see the header: the
    // budget must not feed on itself). A time that is not finite or runs backwards is
    // ignored altogether (the next interval runs from the last good start); an interval
    // shorter than its uploads (a caller's clock mixup) counts as 0.
    if (std::isfinite(now_ms) && (!started_ || now_ms >= last_start_ms_)) {
        if (started_) {
            window_[size_t(next_)] = std::max(0.0, now_ms - last_start_ms_ - last_upload_ms_);
            next_ = (next_ + 1) % kWindow;
            count_ = std::min(count_ + 1, kWindow);
        }
        started_ = true;
        last_start_ms_ = now_ms;
    }
    last_upload_ms_ = 0.0;
    // The median of what the window holds: outliers (the first frame's shader compilation,
    // an idle host) move it by one rank, not by their size. An upper median for even counts.
    if (count_ >= kMinFrames) {
        std::array<double, kWindow> sorted = window_;
        const auto end = sorted.begin() + count_;
        const auto mid = sorted.begin() + count_ / 2;
        std::nth_element(sorted.begin(), mid, end);
        frame_ms_ = *mid;
    }
    const double adaptive =
        count_ >= kMinFrames ? settings_.frame_fraction * frame_ms_ : settings_.floor_ms;
    budget_ms_ = std::max(settings_.floor_ms, std::min(adaptive, settings_.ceiling_ms));
    return budget_ms_;
}

void UploadTimeBudget::endFrame(double upload_ms)
{
    last_upload_ms_ = std::isfinite(upload_ms) ? std::max(0.0, upload_ms) : 0.0;
}

UploadPlanner::UploadPlanner(const PyramidGeometry& geometry, lod::PatchResidency& residency)
    : geometry_(geometry), residency_(residency),
      is_resident_([this](PatchId p) { return resident(p); })
{
    // What a frame keeps and uploads fits in the slots, and the selection should too: room
    // for that from the start, so that no frame grows these (wanted chains may still).
    const size_t slots = size_t(residency.capacity());
    for (std::vector<lod::SelectedPatch>* v :
         {&desired_.patches, &cover_.patches, &outcome_.drawn.patches})
        v->reserve(slots);
    plan_.uploads.reserve(slots);
    needed_list_.reserve(slots);
    needed_.reserve(slots);
    uploading_.reserve(slots);
    wanted_list_.reserve(2 * slots);
    wanted_.reserve(2 * slots);
    plan_.requests.reserve(2 * slots);
}

// Adds `p` to this frame's wanted patches (kDrawn or kDetail); false when it is in already.
bool UploadPlanner::want(PatchId p, double priority, char kind)
{
    if (!wanted_.insert(geometry_.patchIndex(p), kind))
        return false;
    wanted_list_.push_back({p, priority});
    return true;
}

void UploadPlanner::collectWanted(const lod::Selection& desired)
{
    wanted_.clear();
    wanted_list_.clear();
    wantWithChains(desired.patches, requestPriority, kDrawn);
    // Texture detail after all of that, with its own chains (down from a drawn patch).
    wantWithChains(desired.detail, detailPriority, kDetail);
}

// `patches` as `kind` at `priority`, then every ancestor of each up to the finest resident
// one, ahead of it (a coarser level ranks higher). A patch reconstructed on the GPU needs its
// parent resident; and whatever the decoding, the resident cover can only draw a patch once
// all its siblings' areas are covered as finely, so without the levels between, a view of 300
// missing patches would stay the root until the last arrived (issue 22: every frame of a
// bench drew one patch). Coarse first, the view refines level by level instead, for about a
// third more patches.
void UploadPlanner::wantWithChains(const std::vector<lod::SelectedPatch>& patches,
                                   double (*priority)(const PyramidGeometry&, PatchId, double),
                                   char kind)
{
    for (const lod::SelectedPatch& sp : patches)
        want(sp.id, priority(geometry_, sp.id, sp.rank), kind);
    for (const lod::SelectedPatch& sp : patches)
        for (PatchId a = sp.id; a.level > 0 && !resident(a);) {
            a = a.parent();
            if (!want(a, priority(geometry_, a, 0.0), kind))
                break; // the rest of the chain is in already
        }
}

// What the drawn patches' chains hold resident (ancestors not drawn yet, a parent a later
// arrival will be reconstructed from) stays before any texture detail may evict it.
void UploadPlanner::keepWantedChains()
{
    for (const StreamRequest& r : wanted_list_) {
        if (needed_list_.size() >= size_t(residency_.capacity()))
            return;
        if (*wanted_.find(geometry_.patchIndex(r.id)) == kDrawn && resident(r.id))
            need(r.id);
    }
}

// Texture detail stays resident while the slots have room beside what is drawn and uploaded
// (never at their cost: this runs after the drawn patches' uploads were chosen).
void UploadPlanner::keepDetail(const lod::Selection& desired)
{
    for (const lod::SelectedPatch& sp : desired.detail)
        for (PatchId a = sp.id; a.level > 0; a = a.parent()) {
            if (needed_.contains(geometry_.patchIndex(a)))
                break; // drawn, or kept already with the rest of its chain
            if (!resident(a))
                continue; // on its way: its resident ancestors are what it will need
            if (needed_list_.size() >= size_t(residency_.capacity()))
                return;
            need(a);
        }
}

void UploadPlanner::need(PatchId p)
{
    if (needed_.insert(geometry_.patchIndex(p), 1))
        needed_list_.push_back(p);
}

// Coarse first (patch indices run level by level), the caller's order among duplicates.
void UploadPlanner::sortArrived(std::span<const ArrivedPatch> arrived)
{
    order_.resize(arrived.size());
    for (size_t k = 0; k < order_.size(); ++k)
        order_[k] = k;
    std::sort(order_.begin(), order_.end(), [&](size_t a, size_t b) {
        const int64_t ka = geometry_.patchIndex(arrived[a].id);
        const int64_t kb = geometry_.patchIndex(arrived[b].id);
        return ka != kb ? ka < kb : a < b;
    });
}

// Whether `p` is among the arrived patches (sortArrived first). Such a patch is not requested
// again: the streamer would hand it over once more from its RAM cache, every frame it waits.
bool UploadPlanner::hasArrived(PatchId p, std::span<const ArrivedPatch> arrived) const
{
    const int64_t key = geometry_.patchIndex(p);
    auto it = std::lower_bound(order_.begin(), order_.end(), key, [&](size_t pos, int64_t k) {
        return geometry_.patchIndex(arrived[pos].id) < k;
    });
    return it != order_.end() && arrived[*it].id == p;
}

// "Ancestors needed for decoding stay resident": the parent of a patch that waits for GPU
// reconstruction is not evicted, or the patch would wait for its parent's return.
void UploadPlanner::keepParentsOfWaiting(std::span<const ArrivedPatch> arrived)
{
    for (size_t pos : order_) {
        const ArrivedPatch& a = arrived[pos];
        const char* wanted = wanted_.find(geometry_.patchIndex(a.id));
        if (a.needs_parent_resident && wanted && *wanted == kDrawn && !resident(a.id) &&
            resident(a.id.parent()) && needed_list_.size() < size_t(residency_.capacity()))
            need(a.id.parent());
    }
}

// A patch reconstructed on the GPU reads its parent's slot: the parent must be resident and
// kept this frame (not evicted by this frame's uploads), or be uploaded before it.
bool UploadPlanner::parentReady(const ArrivedPatch& a) const
{
    if (!a.needs_parent_resident)
        return true;
    const int64_t parent = geometry_.patchIndex(a.id.parent());
    return uploading_.contains(parent) || (needed_.contains(parent) && resident(a.id.parent()));
}

// The uploads of arrived patches wanted as `kind` (the drawn ones' pass drops what is not
// wanted at all; the detail's comes second, within what the first left of the budget).
void UploadPlanner::chooseUploads(std::span<const ArrivedPatch> arrived, const UploadBudget& budget,
                                  char kind)
{
    size_t planned_bytes = 0;
    for (const PlannedUpload& u : plan_.uploads)
        planned_bytes += u.upload_bytes;
    int64_t previous = -1;
    for (size_t pos : order_) {
        const ArrivedPatch& a = arrived[pos];
        const int64_t key = geometry_.patchIndex(a.id);
        const bool duplicate = key == previous;
        previous = key;
        const char* wanted = wanted_.find(key);
        if (duplicate || !wanted || resident(a.id)) {
            if (kind == kDrawn)
                plan_.dropped.push_back(a.handle);
            continue;
        }
        if (*wanted != kind)
            continue; // the other pass's
        // At least one upload when one is ready, so that streaming always progresses.
        const bool within_budget =
            plan_.uploads.empty() || (int(plan_.uploads.size()) < budget.count &&
                                      planned_bytes + a.upload_bytes <= budget.bytes);
        if (parentReady(a) && within_budget &&
            needed_list_.size() < size_t(residency_.capacity())) {
            planned_bytes += a.upload_bytes;
            need(a.id);
            uploading_.insert(key, 1);
            plan_.uploads.push_back({a.id, -1, a.upload_bytes, a.needs_parent_resident, a.handle});
        } else {
            outcome_.waiting.push_back(a.handle);
        }
    }
}

void UploadPlanner::assignSlots()
{
    const auto loads = residency_.update(needed_list_, residency_.latestFrame() + 1);
    // Everything else needed is resident already, so the loads are exactly the uploads.
    if (loads.size() != plan_.uploads.size())
        throw Error("upload planner: " + std::to_string(loads.size()) + " slots assigned for " +
                    std::to_string(plan_.uploads.size()) + " uploads");
    for (PlannedUpload& u : plan_.uploads)
        u.slot = residency_.slotOf(u.id);
}

// The selector's cover of this frame's selection into cover_ (the quadtree walk's: every
// missing patch drawn by its finest resident ancestor).
void UploadPlanner::coverDesired()
{
    if (selector_)
        selector_->cover(desired_, is_resident_, cover_);
    else
        lod::residentCover(desired_, geometry_, is_resident_, cover_);
}

const StreamPlan& UploadPlanner::plan(const lod::Selection& desired,
                                      std::span<const ArrivedPatch> arrived,
                                      const UploadBudget& budget, lod::PatchSelector* selector)
{
    if (open_)
        throw Error("upload planner: plan() before finish() of the previous plan");
    if (!resident(kRoot))
        throw Error("upload planner: the root patch is not resident");
    plan_.requests.clear();
    plan_.uploads.clear();
    plan_.dropped.clear();
    outcome_.waiting.clear();
    desired_ = desired; // capacity kept
    selector_ = selector;

    collectWanted(desired);
    sortArrived(arrived);
    // Texture detail is requested only once every drawn patch is resident: the streamer's
    // workers (and, on a CPU renderer, the cores drawing the frame) would otherwise decode
    // detail while drawn patches wait — priorities order a queue, not the work already
    // started.
    bool drawn_missing = false;
    for (const StreamRequest& r : wanted_list_) {
        if (resident(r.id))
            continue;
        const bool drawn = *wanted_.find(geometry_.patchIndex(r.id)) == kDrawn;
        if (!drawn && drawn_missing)
            break; // the detail comes after every drawn patch in wanted_list_
        drawn_missing = drawn_missing || drawn;
        if (!hasArrived(r.id, arrived))
            plan_.requests.push_back(r);
    }
    // What this frame keeps: the root, what is drawn now, the parents of waiting patches.
    needed_.clear();
    needed_list_.clear();
    need(kRoot);
    coverDesired();
    for (const lod::SelectedPatch& d : cover_.patches)
        need(d.id);
    keepParentsOfWaiting(arrived);
    uploading_.clear();
    chooseUploads(arrived, budget, kDrawn);
    keepWantedChains();
    keepDetail(desired);
    chooseUploads(arrived, budget, kDetail);
    assignSlots();
    open_ = true;
    return plan_;
}

void UploadPlanner::prefetch(const lod::PatchSelector& selector, const lod::Camera& camera,
                             int frames, const lod::SelectionSettings& settings)
{
    if (!open_)
        throw Error("upload planner: prefetch() outside plan() ... finish()");
    const glm::dvec3 velocity =
        has_last_camera_ ? camera.position() - last_camera_ : glm::dvec3(0.0);
    last_camera_ = camera.position();
    has_last_camera_ = true;
    const std::optional<lod::Camera> future = extrapolatedCamera(camera, velocity, frames);
    if (!future)
        return;
    // Not what this frame wants: a streamer request overwrites the priority, and prefetch's
    // lower one would put this frame's patches behind the future's.
    selector.preview(*future, settings, future_);
    for (const lod::SelectedPatch& sp : future_.patches)
        if (!resident(sp.id) && !wanted_.contains(geometry_.patchIndex(sp.id)))
            plan_.requests.push_back({sp.id, prefetchPriority(geometry_, sp.id, sp.rank)});
}

const StreamOutcome& UploadPlanner::finish(size_t done)
{
    if (!open_)
        throw Error("upload planner: finish() without plan()");
    if (done > plan_.uploads.size())
        throw Error("upload planner: " + std::to_string(done) + " uploads done of " +
                    std::to_string(plan_.uploads.size()));
    open_ = false;
    outcome_.uploaded = int(done);
    // Assigned but never written: free the slots, offer the patches again next frame.
    for (size_t k = done; k < plan_.uploads.size(); ++k) {
        residency_.release(plan_.uploads[k].id);
        outcome_.waiting.push_back(plan_.uploads[k].handle);
    }
    coverDesired();
    outcome_.missing = cover_.missing;
    outcome_.drawn.patches = cover_.patches; // capacity kept
    outcome_.drawn.epsilon_px = desired_.epsilon_px;
    outcome_.drawn.visited = desired_.visited;
    outcome_.drawn.culled = desired_.culled;
    outcome_.drawn.levels_coarser = desired_.levels_coarser;
    return outcome_;
}

} // namespace ridge::stream
