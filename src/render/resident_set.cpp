#include "resident_set.h"

#include "ridge/core/error.h"
#include "ridge/lod/edge_tessellation.h"
#include "ridge/lod/resident_cover.h"
#include "ridge/stream/refinement.h"

#include <algorithm>
#include <array>
#include <exception>
#include <limits>

namespace ridge::render {
namespace {

double millisecondsSince(std::chrono::steady_clock::time_point t0)
{
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

} // namespace

// The codec whose GPU decoder finishes the patches it decodes on the GPU, unless a drawable
// scheme needs codes on the CPU (or --cpu-decode).
const HeightCodec* ResidentSet::gpuDecodedCodec(const archive::ArchiveReader& reader,
                                                const RendererOptions& options,
                                                const SchemePlan& plan)
{
    const HeightCodec& codec = reader.codec();
    return options.streaming && options.gpu_reconstruction && !plan.codes_on_cpu &&
                   codec.capabilities().gpu.first_level >= 0 && findGpuDecoder(codec)
               ? &codec
               : nullptr;
}

ResidentSet::ResidentSet(const archive::ArchiveReader& reader, const lod::PatchQuadtree& quadtree,
                         const RendererOptions& options, int slots, const SchemePlan& plan)
    : reader_(reader), quadtree_(quadtree), options_(options), residency_(reader.geometry(), slots),
      loader_(reader, options.decoded_cache_patches, plan.preparations),
      upload_time_(
          {options.upload_budget_ms, options.upload_frame_fraction, options.upload_budget_max_ms})
{
    const TessellationBlockLayout layout = reader.blockLayout();
    const HeightCodec* gpu_codec = gpuDecodedCodec(reader, options, plan);
    textures_ = std::make_unique<PatchTextures>(
        reader.geometry().patchSize(), layout, std::min(layout.levels(), lod::kMaxBlockLevels),
        slots, reader.quantization(), gpu_codec, PatchTextures::waterMaps(reader));
    if (const lod::ProjectedGrid* grid = quadtree.frame().projectedGrid())
        textures_->setGridAxes(*grid);
    if (options.streaming) {
        stream::StreamerOptions so = stream::StreamerOptions::forRamBudget(
            size_t(options.ram_budget_mb * 1024.0 * 1024.0), options.io_threads);
        so.gpu_decode = gpu_codec != nullptr;
        so.preparations = plan.preparations;
        streamer_ = std::make_unique<stream::PatchStreamer>(reader, so);
    }
}

ResidentSet::~ResidentSet() = default;

void ResidentSet::start(Schemes& schemes)
{
    schemes_ = &schemes;
    if (!streamer_)
        return;
    // The root stays resident: the last resort of every fallback.
    const PatchId root{0, 0, 0};
    for (const lod::PatchResidency::Load& l : residency_.update({root}, ++frame_))
        uploadPatch(*loader_.load(l.id), l.slot);
    computeNormals(root, {});
    textures_->finishUploads();
    planner_ = std::make_unique<stream::UploadPlanner>(reader_.geometry(), residency_);
}

// Makes `patch` resident in `slot`: codes are uploaded, or the codec's GPU decoder finishes
// its CPU half (from the parent's slot when the codec reads it). Slots in `pending_slots` are
// assigned this frame but not yet written: their content must not be read. Returns the bytes sent.
// The normal map follows in computeNormals.
size_t ResidentSet::uploadPatch(const stream::DecodedPatch& patch, int slot,
                                const std::unordered_set<int>& pending_slots)
{
    const PatchId p = patch.id;
    const lod::PatchBounds& bounds = quadtree_.bounds(p);
    const float lambda_cap = bounds.max_height - bounds.min_height;
    if (!patch.decodesOnGpu()) {
        if (!slot_steps_.empty())
            slot_steps_[size_t(slot)].bounds.clear(); // codes: nothing to refine
        textures_->upload(patch, slot, lambda_cap);
        return textures_->uploadBytes(patch) + schemes_->upload(patch, slot);
    }
    int parent_slot = -1;
    if (readsParent(p)) {
        parent_slot = residency_.slotOf(p.parent());
        if (parent_slot < 0 || pending_slots.count(parent_slot))
            throw Error(reader_.describe(p) + ": internal: parent not resident for GPU decoding");
    }
    textures_->decodeOnGpu(patch, parent_slot, slot, stepsFor(patch, slot), lambda_cap);
    ++gpu_decoded_;
    return textures_->uploadBytes(patch);
}

int ResidentSet::stepsFor(const stream::DecodedPatch& patch, int slot)
{
    const auto* refinable = dynamic_cast<const RefinablePayload*>(patch.gpu_payload.get());
    if (!refinable)
        return std::numeric_limits<int>::max();
    if (slot_steps_.empty())
        slot_steps_.resize(size_t(residency_.capacity()));
    SlotSteps& s = slot_steps_[size_t(slot)];
    const int full = refinable->fullSteps();
    s.bounds.assign(size_t(full) + 1, 0.0);
    for (int k = 0; k <= full; ++k)
        s.bounds[size_t(k)] = refinable->stepBound(k);
    s.steps = full;
    if (options_.refine_steps_per_frame > 0) {
        const auto it = view_.find(reader_.geometry().patchIndex(patch.id));
        if (it != view_.end())
            s.steps = stream::stepsForView(*refinable, reader_.quantization().scale,
                                           quadtree_.bounds(patch.id).err, it->second.screen_error,
                                           view_epsilon_px_);
    }
    return s.steps;
}

bool ResidentSet::refine(const lod::Selection& desired, FrameStats& stats)
{
    if (slot_steps_.empty() || options_.refine_steps_per_frame <= 0)
        return false;
    std::vector<const lod::SelectedPatch*> order;
    for (const lod::SelectedPatch& s : desired.patches)
        order.push_back(&s);
    std::sort(order.begin(), order.end(),
              [](const auto* a, const auto* b) { return a->screen_error > b->screen_error; });
    int budget = options_.refine_steps_per_frame;
    for (const lod::SelectedPatch* s : order) {
        const int slot = residency_.slotOf(s->id);
        if (slot < 0 || slot_steps_[size_t(slot)].bounds.empty())
            continue;
        SlotSteps& steps = slot_steps_[size_t(slot)];
        const int wanted =
            stream::stepsForView(steps, reader_.quantization().scale, quadtree_.bounds(s->id).err,
                                 s->screen_error, desired.epsilon_px);
        if (wanted <= steps.steps)
            continue;
        if (budget <= 0) {
            ++stats.under_refined;
            continue;
        }
        const int to = std::min(wanted, steps.steps + budget);
        const lod::PatchBounds& b = quadtree_.bounds(s->id);
        textures_->refine(s->id, slot, to, b.max_height - b.min_height);
        budget -= to - steps.steps;
        stats.refine_steps += to - steps.steps;
        ++stats.refined;
        steps.steps = to;
        stats.under_refined += to < wanted;
        computeNormals(s->id, {});
    }
    return stats.refined > 0;
}

bool ResidentSet::readsParent(PatchId p) const
{
    return p.level > 0 && reader_.codec().capabilities().gpu.parent_resident;
}

size_t ResidentSet::plannedUploadBytes(const stream::DecodedPatch& patch) const
{
    return textures_->uploadBytes(patch) + schemes_->plannedUploadBytes(patch);
}

// The normal map of `p`, just made resident, and those of its resident same-level
// neighbours, whose borders now have a real neighbour instead of an extrapolated one: every
// same-level seam between resident patches gets the same normals on both sides, whatever
// order the patches arrived in. Slots in `pending` (assigned, not yet written) are treated as
// absent; when one is written it refreshes its neighbours in turn.
void ResidentSet::computeNormals(PatchId p, const std::unordered_set<int>& pending)
{
    const PyramidGeometry& g = reader_.geometry();
    auto sidesOf = [](PatchId q) {
        return std::array<PatchId, 4>{
            PatchId{q.level, q.x - 1, q.y}, PatchId{q.level, q.x + 1, q.y},
            PatchId{q.level, q.x, q.y - 1}, PatchId{q.level, q.x, q.y + 1}};
    };
    auto writtenSlot = [&](PatchId q) {
        const int s = g.exists(q) ? residency_.slotOf(q) : -1;
        return s >= 0 && !pending.count(s) ? s : -1;
    };
    auto normalsOf = [&](PatchId q) {
        std::array<int, 4> neighbours{-1, -1, -1, -1};
        if (options_.seamless_normals) {
            const std::array<PatchId, 4> sides = sidesOf(q);
            for (size_t k = 0; k < 4; ++k)
                neighbours[k] = writtenSlot(sides[k]);
        }
        const double step = double(g.step(q.level));
        const lod::TerrainFrame& frame = quadtree_.frame();
        if (frame.projectedGrid()) {
            const int64_t span = int64_t(g.cells()) * int64_t(step);
            textures_->computeNormalsOnGrid(residency_.slotOf(q), neighbours, q.x * span,
                                            q.y * span, int64_t(step));
            return;
        }
        if (frame.onEllipsoid()) {
            // Metres per cell on the ellipsoid: along a parallel they shrink with cos φ.
            const lod::GeodeticGrid& geo = frame.geodetic();
            const double row0 = double(q.y) * g.cells() * step;
            textures_->computeNormals(residency_.slotOf(q), neighbours,
                                      step * geo.dlon * geo.ellipsoid.a,
                                      step * std::abs(geo.dlat) * geo.ellipsoid.a,
                                      frame.latitudeOf(row0), step * geo.dlat);
            return;
        }
        textures_->computeNormals(residency_.slotOf(q), neighbours,
                                  step * reader_.header().spacing_x,
                                  step * reader_.header().spacing_y);
    };
    normalsOf(p);
    if (options_.seamless_normals)
        for (PatchId q : sidesOf(p))
            if (writtenSlot(q) >= 0)
                normalsOf(q);
}

void ResidentSet::makeResident(const lod::Selection& selection, FrameStats& stats)
{
    // Texture detail too (the selection keeps both within the slots).
    std::vector<PatchId> ids;
    ids.reserve(selection.patches.size() + selection.detail.size());
    for (const lod::SelectedPatch& s : selection.patches)
        ids.push_back(s.id);
    for (const lod::SelectedPatch& s : selection.detail)
        ids.push_back(s.id);
    const auto loads = residency_.update(ids, ++frame_);
    std::unordered_set<int> pending;
    for (const lod::PatchResidency::Load& l : loads)
        pending.insert(l.slot);
    for (size_t k = 0; k < loads.size(); ++k) {
        try {
            stats.bytes_uploaded += uploadPatch(*loader_.load(loads[k].id), loads[k].slot);
        } catch (...) {
            // The failed patch and those after it were given slots they never filled.
            for (size_t j = k; j < loads.size(); ++j)
                residency_.release(loads[j].id);
            textures_->finishUploads();
            throw;
        }
        pending.erase(loads[k].slot);
        computeNormals(loads[k].id, pending);
    }
    if (!loads.empty())
        textures_->finishUploads();
    stats.loaded = int(loads.size());
    stats.resident = residency_.residentCount();
}

// Streaming, executed: the GL-free stream::UploadPlanner decides what to request, what stays
// resident, what to upload this frame and into which slot; this uploads it (stopping when the
// time budget is spent) and tells the planner how far it got. The planner is called here
// alone: plan (with prefetch) before the uploads, finish after them.
lod::Selection ResidentSet::stream(const lod::Selection& desired, lod::PatchSelector& selector,
                                   const lod::Camera& camera,
                                   const lod::SelectionSettings& settings, FrameStats& stats)
{
    // Each streamed frame's time budget follows the frame time (stream::UploadTimeBudget).
    stats.upload_budget_ms = upload_time_.beginFrame(millisecondsSince(epoch_));
    streamer_->beginFrame();
    view_.clear();
    view_epsilon_px_ = desired.epsilon_px;
    if (options_.refine_steps_per_frame > 0 && reader_.codec().capabilities().gpu.refinable)
        for (const lod::SelectedPatch& s : desired.patches)
            view_.emplace(reader_.geometry().patchIndex(s.id), s);
    for (auto& patch : streamer_->takeReady())
        arrived_.push_back(std::move(patch));
    arrived_descriptions_.clear();
    for (size_t k = 0; k < arrived_.size(); ++k)
        arrived_descriptions_.push_back(
            {arrived_[k]->id, plannedUploadBytes(*arrived_[k]),
             arrived_[k]->decodesOnGpu() && readsParent(arrived_[k]->id), k});
    const stream::StreamPlan& plan = planner_->plan(
        desired, arrived_descriptions_,
        {size_t(options_.upload_budget_mb * 1024.0 * 1024.0), options_.uploads_per_frame},
        &selector);
    planner_->prefetch(selector, camera, options_.prefetch_frames, settings);
    for (const stream::StreamRequest& r : plan.requests)
        streamer_->request(r.id, r.priority);

    std::unordered_set<int> pending_slots;
    for (const stream::PlannedUpload& u : plan.uploads)
        pending_slots.insert(u.slot);
    // Coarse first (the plan's order), so that a parent uploaded this frame is written before
    // its children.
    const auto t0 = std::chrono::steady_clock::now();
    const int gpu_decoded_before = gpu_decoded_;
    size_t done = 0;
    std::exception_ptr failure;
    try {
        for (; done < plan.uploads.size(); ++done) {
            if (!upload_time_.mayStart(done, millisecondsSince(t0)))
                break; // the time budget: the rest waits for the next frame
            const stream::PlannedUpload& u = plan.uploads[done];
            stats.bytes_uploaded += uploadPatch(*arrived_[u.handle], u.slot, pending_slots);
            pending_slots.erase(u.slot);
            computeNormals(u.id, pending_slots); // inside the time budget too
        }
    } catch (...) {
        failure = std::current_exception();
    }
    const double upload_ms = done > 0 ? millisecondsSince(t0) : 0.0;
    // After a failure, the failed upload and those after it give their slots back.
    const stream::StreamOutcome& outcome = planner_->finish(done);
    if (failure)
        std::rethrow_exception(failure);
    upload_time_.endFrame(upload_ms);
    const bool refined = refine(desired, stats);
    waiting_.clear();
    for (size_t h : outcome.waiting)
        waiting_.push_back(std::move(arrived_[h]));
    arrived_.swap(waiting_);
    if (done > 0 || refined)
        textures_->finishUploads();
    stats.loaded = outcome.uploaded;
    stats.reconstructed = gpu_decoded_ - gpu_decoded_before;
    stats.missing = outcome.missing;
    stats.resident = residency_.residentCount();
    return outcome.drawn;
}

lod::Selection ResidentSet::cover(lod::Selection selection, lod::PatchSelector& selector) const
{
    lod::ResidentCover drawn;
    selector.cover(
        selection, [&](PatchId p) { return residency_.slotOf(p) >= 0; }, drawn);
    selection.patches = std::move(drawn.patches);
    return selection;
}

void ResidentSet::countTraffic(FrameStats& stats)
{
    if (streamer_) {
        const stream::StreamerStats now = streamer_->stats();
        stats.bytes_read = now.bytes_read - last_streamer_stats_.bytes_read;
        stats.bytes_decoded = now.bytes_decoded - last_streamer_stats_.bytes_decoded;
        stats.cache_hits = int(now.cache_hits - last_streamer_stats_.cache_hits);
        stats.cache_misses = int(now.requested - last_streamer_stats_.requested);
        last_streamer_stats_ = now;
    } else {
        const stream::LoaderStats& now = loader_.stats();
        stats.bytes_read = now.bytes_read - last_loader_stats_.bytes_read;
        stats.cache_hits = int(now.cache_hits - last_loader_stats_.cache_hits);
        stats.cache_misses = int(now.decoded - last_loader_stats_.decoded);
        stats.bytes_decoded = now.bytes_decoded - last_loader_stats_.bytes_decoded;
        last_loader_stats_ = now;
    }
}

void ResidentSet::waitIdle()
{
    if (streamer_)
        streamer_->waitIdle();
}

bool ResidentSet::waitIdleFor(double timeout_seconds)
{
    return !streamer_ || streamer_->waitIdleFor(timeout_seconds);
}

std::string ResidentSet::error() const
{
    return streamer_ ? streamer_->error() : std::string();
}

size_t ResidentSet::cacheBytes() const
{
    if (!streamer_)
        return 0;
    const stream::StreamerStats s = streamer_->stats();
    return s.cache_bytes + s.compressed_bytes;
}

uint64_t ResidentSet::cacheMisses() const
{
    return streamer_ ? streamer_->stats().requested : loader_.stats().decoded;
}

uint64_t ResidentSet::cacheHits() const
{
    return streamer_ ? streamer_->stats().cache_hits : loader_.stats().cache_hits;
}

} // namespace ridge::render
