// The streaming policy driven over simulated frames, without GL: a fake streamer (a queue that
// delivers what was requested a few frames later), a fake GPU (what each slot holds) and the
// executor loop the renderer runs (plan, upload in order, maybe stop early, finish, draw).
#include "allocation_counter.h"

#include "ridge/core/error.h"
#include "ridge/lod/rings.h"
#include "ridge/stream/upload_planner.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <random>
#include <set>

using namespace ridge;
using namespace ridge::stream;

namespace {

bool isAncestorOrSelf(PatchId a, PatchId p)
{
    while (p.level > a.level)
        p = p.parent();
    return p == a;
}

// A quadtree without an archive: heights and Err(P) halving per level.
lod::PatchQuadtree syntheticTree(const PyramidGeometry& g)
{
    std::vector<lod::PatchBounds> bounds(size_t(g.patchCount()));
    for (int64_t i = 0; i < g.patchCount(); ++i)
        bounds[size_t(i)] = {0.f, 500.f, 64.f / float(1 << g.patchAt(i).level)};
    return lod::PatchQuadtree(lod::TerrainFrame(g, 10.0, 10.0), bounds);
}

lod::Camera randomCamera(std::mt19937& rng)
{
    return lod::Camera({double(rng() % 10000), double(rng() % 7000), 200.0 + rng() % 2000},
                       {5000, 3500, 0}, 60.0, {1280, 720}, 1.0, 1e6);
}

// PatchStreamer's contract in miniature: a request is delivered `delay` frames after it was
// first made, unless it went a frame without renewal (stale, dropped).
class FakeStreamer {
  public:
    FakeStreamer(const PyramidGeometry& g, int delay) : g_(g), delay_(delay) {}
    // Delivers patches of this level only (< 0: all); the others stay pending forever.
    void deliverOnlyLevel(int level) { only_level_ = level; }
    void beginFrame(int frame)
    {
        frame_ = frame;
        std::erase_if(pending_, [&](const auto& kv) { return kv.second.renewed < frame - 1; });
    }
    void request(PatchId p, double priority)
    {
        EXPECT_TRUE(std::isfinite(priority));
        auto [it, fresh] = pending_.try_emplace(g_.patchIndex(p), Pending{p, frame_ + delay_, 0});
        it->second.renewed = frame_;
    }
    std::vector<PatchId> takeReady()
    {
        std::vector<PatchId> out;
        for (auto it = pending_.begin(); it != pending_.end();)
            if (it->second.due <= frame_ &&
                (only_level_ < 0 || it->second.id.level == only_level_)) {
                out.push_back(it->second.id);
                it = pending_.erase(it);
            } else {
                ++it;
            }
        return out;
    }

  private:
    struct Pending {
        PatchId id;
        int due = 0;
        int renewed = 0;
    };
    PyramidGeometry g_;
    int delay_ = 0;
    int frame_ = 0;
    int only_level_ = -1;
    std::map<int64_t, Pending> pending_;
};

// Bytes an upload of `p` sends: varied, so that byte budgets bind at different counts.
size_t uploadBytes(PatchId p)
{
    return 2000 + size_t(p.level % 3) * 700 + size_t(p.x % 2) * 300;
}

struct FrameReport {
    size_t requests = 0;
    size_t uploads = 0;
    size_t not_done = 0; // planned, then left by the executor's time budget
    int reconstructed = 0;
    int missing = 0;
    size_t drawn = 0;       // patches of the resident cover drawn this frame
    size_t allocations = 0; // by plan() and finish()
};

// The executor: the renderer's loop with a fake GPU (slot -> patch written there).
class Simulation {
  public:
    Simulation(const PyramidGeometry& g, int slots, bool gpu_reconstruction, int delay)
        : g_(g), gpu_reconstruction_(gpu_reconstruction), residency_(g, slots),
          planner_(g, residency_), streamer_(g, delay), written_(size_t(slots))
    {
        // The renderer loads the root synchronously before streaming starts.
        for (const lod::PatchResidency::Load& l : residency_.update({PatchId{}}, 1))
            written_[size_t(l.slot)] = l.id;
    }

    // One frame. `stop_after`: where the executor's time budget ends (SIZE_MAX: it does all).
    FrameReport frame(const lod::Selection& desired, const UploadBudget& budget,
                      size_t stop_after = SIZE_MAX)
    {
        streamer_.beginFrame(++frame_);
        for (PatchId p : streamer_.takeReady())
            arrived_.push_back(p);
        descriptors_.clear();
        for (size_t k = 0; k < arrived_.size(); ++k)
            descriptors_.push_back({arrived_[k], uploadBytes(arrived_[k]),
                                    gpu_reconstruction_ && arrived_[k].level > 0, k});

        FrameReport report;
        std::optional<test::AllocationCounter> counter(std::in_place);
        const StreamPlan& plan = planner_.plan(desired, descriptors_, budget, selector_);
        report.allocations += counter->count();
        counter.reset();
        checkPlan(plan, desired, budget);
        // Texture detail is requested only in frames that request nothing for drawing.
        bool drawn_requested = false, detail_requested = false;
        for (const StreamRequest& r : plan.requests)
            (wantedByTest(r.id, desired) ? drawn_requested : detail_requested) = true;
        EXPECT_FALSE(drawn_requested && detail_requested);
        for (const StreamRequest& r : plan.requests)
            streamer_.request(r.id, r.priority);
        const size_t done = std::min(stop_after, plan.uploads.size());
        for (size_t k = 0; k < done; ++k)
            upload(plan.uploads[k]);
        std::vector<PlannedUpload> not_done(plan.uploads.begin() + std::ptrdiff_t(done),
                                            plan.uploads.end());
        report.requests = plan.requests.size();
        report.uploads = done;
        report.not_done = plan.uploads.size() - done;
        std::vector<size_t> dropped = plan.dropped;

        for (size_t k = 0; k < done; ++k)
            report.reconstructed += plan.uploads[k].needs_parent_resident;
        counter.emplace();
        const StreamOutcome& outcome = planner_.finish(done);
        report.allocations += counter->count();
        counter.reset();
        for (const PlannedUpload& u : not_done)
            EXPECT_LT(residency_.slotOf(u.id), 0) << "a slot assigned but never written stays";
        checkHandles(dropped, done, outcome.waiting);
        checkCover(outcome.drawn, desired);
        report.missing = outcome.missing;
        report.drawn = outcome.drawn.patches.size();
        std::vector<PatchId> kept;
        for (size_t h : outcome.waiting)
            kept.push_back(arrived_[h]);
        arrived_.swap(kept);
        return report;
    }

    bool allResident(const lod::Selection& s) const
    {
        for (const lod::SelectedPatch& p : s.patches)
            if (residency_.slotOf(p.id) < 0)
                return false;
        return true;
    }
    const lod::PatchResidency& residency() const { return residency_; }
    // A scheme's own selector: its cover is drawn (and checked by the caller) instead of
    // the quadtree walk's resident cover.
    void useSelector(lod::PatchSelector* selector) { selector_ = selector; }
    UploadPlanner& planner() { return planner_; }
    FakeStreamer& streamer() { return streamer_; }
    size_t waiting() const { return arrived_.size(); }

  private:
    // Wanted this frame for drawing: a desired patch or an ancestor of one (whatever the
    // decoding: the view refines level by level).
    bool wantedByTest(PatchId p, const lod::Selection& desired) const
    {
        for (const lod::SelectedPatch& s : desired.patches)
            if (isAncestorOrSelf(p, s.id))
                return true;
        return false;
    }

    void checkPlan(const StreamPlan& plan, const lod::Selection& desired,
                   const UploadBudget& budget)
    {
        size_t bytes = 0;
        std::set<int> slots;
        for (const PlannedUpload& u : plan.uploads) {
            bytes += u.upload_bytes;
            ASSERT_GE(u.slot, 0);
            ASSERT_LT(u.slot, residency_.capacity());
            EXPECT_TRUE(slots.insert(u.slot).second) << "two uploads into one slot";
            EXPECT_EQ(residency_.slotOf(u.id), u.slot);
        }
        EXPECT_LE(residency_.residentCount(), residency_.capacity());
        if (plan.uploads.size() > 1) {
            EXPECT_LE(int(plan.uploads.size()), budget.count);
            EXPECT_LE(bytes, budget.bytes);
        }
        // The drawn patches' uploads first, coarse first; then texture detail's, coarse first
        // (a parent is written before its children either way).
        auto isDetail = [&](PatchId p) {
            for (const lod::SelectedPatch& d : desired.detail)
                if (isAncestorOrSelf(p, d.id))
                    return !wantedByTest(p, desired);
            return false;
        };
        for (size_t k = 1; k < plan.uploads.size(); ++k) {
            const PatchId a = plan.uploads[k - 1].id, b = plan.uploads[k].id;
            EXPECT_FALSE(isDetail(a) && !isDetail(b)) << "texture detail before a drawn patch";
            if (isDetail(a) == isDetail(b)) {
                EXPECT_LE(a.level, b.level) << "coarse first";
            }
        }
        // Something ready waits: at least one upload (the tests give slots to spare).
        bool ready = false;
        for (PatchId p : arrived_) {
            // Resident now may mean "uploaded by this plan"; a ready one is enough.
            const bool parent_ok = !gpu_reconstruction_ || p.level == 0 || written(p.parent());
            ready = ready || (wantedByTest(p, desired) && !written(p) && parent_ok);
        }
        // Only without evictions is "wanted" as simple as wantedByTest.
        if (ready && residency_.evictions() == 0 &&
            4 * desired.patches.size() + 16 < size_t(residency_.capacity())) {
            EXPECT_FALSE(plan.uploads.empty()) << "a ready patch waits with nothing uploaded";
        }
    }

    bool written(PatchId p) const
    {
        const int s = residency_.slotOf(p);
        return s >= 0 && written_[size_t(s)] == p;
    }

    void upload(const PlannedUpload& u)
    {
        // GPU reconstruction reads the parent's slot: it must hold the parent now.
        if (u.needs_parent_resident) {
            EXPECT_TRUE(written(u.id.parent()))
                << "patch (" << u.id.level << "," << u.id.x << "," << u.id.y
                << ") reconstructed without its parent resident";
        }
        written_[size_t(u.slot)] = u.id;
    }

    // Every arrived patch is accounted for exactly once: dropped, uploaded or waiting.
    void checkHandles(const std::vector<size_t>& dropped, size_t done,
                      const std::vector<size_t>& waiting)
    {
        std::multiset<size_t> all(dropped.begin(), dropped.end());
        all.insert(waiting.begin(), waiting.end());
        EXPECT_EQ(all.size() + done, arrived_.size());
        EXPECT_EQ(std::set<size_t>(all.begin(), all.end()).size(), all.size());
    }

    // No hole, no overlap, nothing drawn from a slot that does not hold it.
    void checkCover(const lod::Selection& drawn, const lod::Selection& desired)
    {
        for (const lod::SelectedPatch& d : drawn.patches)
            EXPECT_TRUE(written(d.id)) << "drawn patch not resident";
        if (selector_)
            return; // the selector's own rule: its tests check it
        for (const lod::SelectedPatch& s : desired.patches) {
            int under = 0;
            for (const lod::SelectedPatch& d : drawn.patches)
                under += isAncestorOrSelf(d.id, s.id) || isAncestorOrSelf(s.id, d.id);
            EXPECT_EQ(under, 1) << "desired patch covered " << under << " times";
        }
    }

    PyramidGeometry g_;
    bool gpu_reconstruction_ = false;
    lod::PatchResidency residency_;
    UploadPlanner planner_;
    FakeStreamer streamer_;
    std::vector<std::optional<PatchId>> written_; // the fake GPU
    std::vector<PatchId> arrived_;                // the executor's list of decoded patches
    std::vector<ArrivedPatch> descriptors_;
    lod::PatchSelector* selector_ = nullptr;
    int frame_ = 0;
};

const PyramidGeometry kGeometry(1000, 700, 33);

lod::Selection select(const lod::PatchQuadtree& tree, const lod::Camera& camera, size_t max)
{
    lod::SelectionSettings settings;
    settings.max_patches = max;
    return tree.select(camera, settings);
}

} // namespace

TEST(UploadPlanner, TheAllocationCounterCounts)
{
    test::AllocationCounter counter;
    auto v = std::make_unique<std::vector<int>>(10);
    EXPECT_EQ(counter.count(), 2u);
}

TEST(UploadPlanner, StreamsAFixedViewInFullWithinBudgetsThenPlansWithoutAllocating)
{
    const lod::PatchQuadtree tree = syntheticTree(kGeometry);
    std::mt19937 rng(3);
    for (bool gpu : {false, true}) {
        Simulation sim(kGeometry, 4096, gpu, 2);
        const lod::Selection desired = select(tree, randomCamera(rng), 512);
        ASSERT_GT(desired.patches.size(), 20u);
        const UploadBudget budget{3 * 2600, 4}; // binds by bytes or count, patch by patch
        int frames = 0;
        for (; frames < 500 && !(sim.allResident(desired) && sim.waiting() == 0); ++frames) {
            // The executor's time budget ends early now and then (at 0 too).
            const size_t stop = rng() % 4 == 0 ? size_t(rng() % 3) : SIZE_MAX;
            sim.frame(desired, budget, stop);
        }
        ASSERT_TRUE(sim.allResident(desired)) << "gpu " << gpu << " after " << frames;
        for (int k = 0; k < 100; ++k) {
            const FrameReport r = sim.frame(desired, budget);
            EXPECT_EQ(r.missing, 0);
            EXPECT_EQ(r.uploads, 0u);
            EXPECT_EQ(r.requests, 0u);
            ASSERT_EQ(r.allocations, 0u) << "steady frame " << k << ", gpu " << gpu;
        }
    }
}

TEST(UploadPlanner, StreamsAMovingRingsViewThroughItsOwnSelectorAndCoverThenPlansWithoutAllocating)
{
    // The other kind of selection: scheme rings' selector (distance rings, its own cover).
    // The planner's rules hold for it too: budgets, parents before GPU reconstruction,
    // everything drawn resident, no allocation once a view has streamed in.
    const PyramidGeometry g(4097, 2049, 65); // 64 × 32 tiles, 7 levels
    const lod::PatchQuadtree tree = syntheticTree(g);
    for (bool gpu : {false, true}) {
        lod::RingsSelector rings(tree, lod::RingsSettings{4, 1});
        Simulation sim(g, 256, gpu, 2);
        sim.useSelector(&rings);
        const UploadBudget budget{3 * 2600, 4};
        lod::SelectionSettings settings;
        settings.max_patches = 256;
        lod::Selection desired;
        auto checkTiles = [&](const char* when) {
            for (const lod::RingTile& t : rings.drawnTiles()) {
                ASSERT_GE(sim.residency().slotOf(rings.ancestorOf(t.x, t.y, t.level)), 0) << when;
                if (t.stitch) {
                    ASSERT_GE(sim.residency().slotOf(rings.ancestorOf(t.x, t.y, t.level - 1)), 0)
                        << when;
                }
            }
        };
        // A walk east along the terrain: the centre moves tile by tile (updateRings).
        for (int step = 0; step < 40; ++step) {
            const double x = 500.0 + 400.0 * step, y = 5000.0;
            const lod::Camera cam({x, y, 800.0}, {x + 3000.0, y + 400.0, 0.0}, 60.0, {640, 360},
                                  1.0, 1e6);
            rings.select(cam, settings, desired);
            sim.frame(desired, budget);
            checkTiles("walking");
        }
        int frames = 0;
        for (; frames < 800 && !(sim.allResident(desired) && sim.waiting() == 0); ++frames) {
            sim.frame(desired, budget);
            checkTiles("settling");
        }
        ASSERT_TRUE(sim.allResident(desired)) << "gpu " << gpu << " after " << frames;
        EXPECT_EQ(rings.lowered(), 0);
        for (int k = 0; k < 50; ++k) {
            const FrameReport r = sim.frame(desired, budget);
            EXPECT_EQ(r.missing, 0);
            EXPECT_EQ(r.uploads, 0u);
            ASSERT_EQ(r.allocations, 0u) << "steady frame " << k << ", gpu " << gpu;
        }
    }
}

TEST(UploadPlanner, TheViewRefinesLevelByLevelWhileTheSelectionStreamsWhateverTheDecoding)
{
    // Issue 22: with patches decoded on the CPU, only the selection was requested, and the
    // resident cover (which must tile) drew the root alone until the last selected patch
    // arrived. With the ancestors requested coarse first, the drawn patches multiply long
    // before full detail.
    const lod::PatchQuadtree tree = syntheticTree(kGeometry);
    std::mt19937 rng(5);
    for (bool gpu : {false, true}) {
        Simulation sim(kGeometry, 4096, gpu, 1);
        const lod::Selection desired = select(tree, randomCamera(rng), 512);
        ASSERT_GT(desired.patches.size(), 40u);
        const UploadBudget budget{1 << 20, 4}; // four uploads a frame
        int frames = 0, first_refined = -1;
        for (; frames < 500 && !(sim.allResident(desired) && sim.waiting() == 0); ++frames) {
            const FrameReport r = sim.frame(desired, budget);
            if (first_refined < 0 && r.drawn > 1)
                first_refined = frames;
        }
        ASSERT_TRUE(sim.allResident(desired));
        std::printf("gpu %d: %zu patches selected, more than the root drawn from frame %d, full "
                    "detail at frame %d\n",
                    int(gpu), desired.patches.size(), first_refined, frames);
        EXPECT_GE(first_refined, 0);
        EXPECT_LT(first_refined, frames / 4) << "gpu " << gpu;
    }
}

TEST(UploadPlanner, HoldsItsRulesWhileTheViewJumpsAndSlotsRunShort)
{
    const lod::PatchQuadtree tree = syntheticTree(kGeometry);
    std::mt19937 rng(11);
    for (bool gpu : {false, true})
        for (int slots : {24, 64, 4096}) {
            Simulation sim(kGeometry, slots, gpu, 1 + int(rng() % 3));
            lod::Selection desired;
            FrameReport total; // that the run exercised what it checks
            for (int frame = 0; frame < 300; ++frame) {
                if (frame % 7 == 0) // the renderer caps the selection at the slot count
                    desired = select(tree, randomCamera(rng), size_t(slots));
                const UploadBudget budget{size_t(2000 + rng() % 12000), 1 + int(rng() % 6)};
                const size_t stop = rng() % 3 == 0 ? size_t(rng() % 4) : SIZE_MAX;
                const FrameReport r = sim.frame(desired, budget, stop);
                total.uploads += r.uploads;
                total.not_done += r.not_done;
                total.reconstructed += r.reconstructed;
                total.missing += r.missing;
                ASSERT_FALSE(testing::Test::HasFailure())
                    << "gpu " << gpu << ", slots " << slots << ", frame " << frame;
            }
            EXPECT_GT(total.uploads, 100u);
            EXPECT_GT(total.not_done, 0u);
            EXPECT_GT(total.missing, 0);
            EXPECT_EQ(total.reconstructed > 0, gpu);
            EXPECT_EQ(sim.residency().evictions() > 0, slots < 4096) << slots;
        }
}

TEST(UploadPlanner, PlansWithoutAllocatingWhilePatchesWaitForTheirParents)
{
    // GPU reconstruction of a finest patch whose ancestors never arrive: it waits every
    // frame while the chain is requested again. Steady too: nothing may allocate.
    Simulation sim(kGeometry, 64, true, 1);
    sim.streamer().deliverOnlyLevel(kGeometry.finestLevel());
    lod::Selection desired;
    desired.patches.push_back({PatchId{kGeometry.finestLevel(), 3, 2}, 1.0});
    desired.patches.push_back({PatchId{1, 1, 1}, 1.0});
    const UploadBudget budget;
    for (int k = 0; k < 3; ++k)
        sim.frame(desired, budget); // vectors and tables grow here
    ASSERT_EQ(sim.waiting(), 1u);
    for (int k = 0; k < 100; ++k) {
        const FrameReport r = sim.frame(desired, budget);
        // The chain above the arrived patch (levels finest − 1 to 1) and (1, 1, 1).
        EXPECT_EQ(r.requests, size_t(kGeometry.finestLevel()));
        EXPECT_EQ(r.uploads, 0u);
        EXPECT_EQ(sim.waiting(), 1u);
        EXPECT_EQ(r.missing, 2);
        ASSERT_EQ(r.allocations, 0u) << "frame " << k;
    }
}

TEST(UploadPlanner, ReleasesTheSlotsOfUploadsNotDoneAndKeepsThosePatches)
{
    lod::PatchResidency residency(kGeometry, 16);
    (void)residency.update({PatchId{}}, 1);
    UploadPlanner planner(kGeometry, residency);
    lod::Selection desired;
    std::vector<ArrivedPatch> arrived;
    for (int k = 0; k < 4; ++k) {
        const PatchId p{1, k & 1, k >> 1};
        desired.patches.push_back({p, 1.0});
        arrived.push_back({p, 100, false, size_t(10 + k)});
    }
    arrived.push_back({PatchId{2, 0, 0}, 100, false, 99}); // not wanted: dropped
    const StreamPlan& plan = planner.plan(desired, arrived, UploadBudget{1000, 3});
    ASSERT_EQ(plan.uploads.size(), 3u);
    EXPECT_EQ(plan.dropped, std::vector<size_t>{99});
    EXPECT_THROW(planner.plan(desired, arrived, UploadBudget{}), Error);
    const PatchId second = plan.uploads[1].id, third = plan.uploads[2].id;
    const StreamOutcome& outcome = planner.finish(1);
    EXPECT_EQ(outcome.uploaded, 1);
    EXPECT_LT(residency.slotOf(second), 0);
    EXPECT_LT(residency.slotOf(third), 0);
    EXPECT_EQ(outcome.waiting.size(), 3u); // the one over budget and the two not done
    EXPECT_EQ(outcome.missing, 3);
    EXPECT_EQ(outcome.drawn.patches.size(), 1u); // the root stands in for all four
    EXPECT_THROW(planner.finish(0), Error);
}

TEST(UploadPlanner, RefusesToPlanWithoutTheRoot)
{
    lod::PatchResidency residency(kGeometry, 16);
    UploadPlanner planner(kGeometry, residency);
    EXPECT_THROW(planner.plan(lod::Selection{}, {}, UploadBudget{}), Error);
}

TEST(UploadPlanner, RequestsCoarseBeforeFineAndPrefetchBelowEverything)
{
    const PyramidGeometry& g = kGeometry;
    EXPECT_GT(requestPriority(g, {1, 0, 0}, 0.0), requestPriority(g, {2, 0, 0}, 1e9));
    EXPECT_GT(requestPriority(g, {2, 0, 0}, 5.0), requestPriority(g, {2, 1, 0}, 4.0));
    EXPECT_LT(prefetchPriority(g, {0, 0, 0}, 1e9), requestPriority(g, {g.finestLevel(), 0, 0}, 0));

    const lod::PatchQuadtree tree = syntheticTree(g);
    lod::PatchResidency residency(g, 4096);
    (void)residency.update({PatchId{}}, 1);
    UploadPlanner planner(g, residency);
    const lod::Camera a({2000, 1000, 800}, {5000, 3500, 0}, 60.0, {1280, 720}, 1.0, 1e6);
    const lod::Camera b({2100, 1050, 800}, {5100, 3550, 0}, 60.0, {1280, 720}, 1.0, 1e6);
    lod::SelectionSettings settings;
    EXPECT_FALSE(extrapolatedCamera(a, glm::dvec3(0.0), 20));
    EXPECT_FALSE(extrapolatedCamera(a, glm::dvec3(1.0), 0));
    for (const lod::Camera* camera : {&a, &b}) {
        const lod::Selection desired = tree.select(*camera, settings);
        const StreamPlan& plan = planner.plan(desired, {}, UploadBudget{});
        const size_t now = plan.requests.size();
        planner.prefetch(tree, *camera, 20, settings);
        double lowest_now = 1e300;
        std::set<int64_t> keys;
        for (size_t k = 0; k < plan.requests.size(); ++k) {
            const StreamRequest& r = plan.requests[k];
            EXPECT_TRUE(keys.insert(g.patchIndex(r.id)).second) << "requested twice";
            EXPECT_LT(residency.slotOf(r.id), 0);
            if (k < now) {
                lowest_now = std::min(lowest_now, r.priority);
            } else {
                EXPECT_LT(r.priority, lowest_now);
            }
        }
        // The first frame has no velocity; the second looks ahead of b.
        EXPECT_EQ(plan.requests.size() > now, camera == &b);
        planner.finish(0);
    }
    EXPECT_THROW(planner.prefetch(tree, b, 20, settings), Error);
}

// Texture detail (lod::Selection::detail) streams after the drawn patches and never holds
// them back: with slots short, frame by frame, the drawn patches' missing count is the same
// as without any detail; the detail's requests rank below every drawn patch's; what detail
// fits stays resident.
TEST(UploadPlanner, StreamsTextureDetailAfterTheDrawnPatchesWithoutHoldingThemBack)
{
    const PyramidGeometry& g = kGeometry;
    const lod::PatchQuadtree tree = syntheticTree(g);
    const lod::Camera camera({2000, 1000, 600}, {5000, 3500, 0}, 60.0, {1280, 720}, 1.0, 1e6);
    lod::SelectionSettings settings;
    settings.epsilon_px = 8.0;
    settings.texel_px = 0.5;
    const lod::Selection desired = tree.select(camera, settings);
    ASSERT_GT(desired.detail.size(), 8u);
    lod::Selection plain = desired;
    plain.detail.clear();
    for (const bool gpu : {false, true}) {
        // Room for the drawn patches, their chains and a few detail patches.
        const int slots = int(desired.patches.size()) + 24;
        Simulation with(g, slots, gpu, 2), without(g, slots, gpu, 2);
        const UploadBudget budget{size_t(1) << 20, 4};
        for (int frame = 0; frame < 60; ++frame) {
            const FrameReport a = with.frame(desired, budget);
            const FrameReport b = without.frame(plain, budget);
            ASSERT_EQ(a.missing, b.missing) << "frame " << frame << (gpu ? " (GPU)" : "");
            ASSERT_EQ(a.drawn, b.drawn) << "frame " << frame;
        }
        EXPECT_TRUE(with.allResident(desired));
        // The slots left over hold texture detail (leaves, or the levels on the way to them).
        std::set<int64_t> detail;
        for (const lod::SelectedPatch& d : desired.detail)
            for (PatchId p = d.id; !std::any_of(
                     desired.patches.begin(), desired.patches.end(),
                     [&](const lod::SelectedPatch& s) { return isAncestorOrSelf(p, s.id); });
                 p = p.parent())
                if (with.residency().slotOf(p) >= 0)
                    detail.insert(g.patchIndex(p));
        EXPECT_GT(detail.size(), 0u);
        EXPECT_EQ(with.residency().residentCount(), slots);
        // Steady: what is resident stays (no churn between detail patches).
        const uint64_t evictions = with.residency().evictions();
        for (int frame = 0; frame < 10; ++frame)
            (void)with.frame(desired, budget);
        EXPECT_EQ(with.residency().evictions(), evictions);
    }

    // Requests: none for detail while anything drawn is requested; then every detail patch
    // (and the levels on the way to it), ranked below any drawn patch and above prefetch.
    lod::PatchResidency residency(g, 4096);
    (void)residency.update({PatchId{}}, 1);
    UploadPlanner planner(g, residency);
    auto isDrawnChain = [&](PatchId p) {
        return std::any_of(desired.patches.begin(), desired.patches.end(),
                           [&](const lod::SelectedPatch& d) { return isAncestorOrSelf(p, d.id); });
    };
    for (const StreamRequest& r : planner.plan(desired, {}, UploadBudget{}).requests)
        EXPECT_TRUE(isDrawnChain(r.id)) << "detail requested while drawn patches are missing";
    planner.finish(0);
    std::vector<PatchId> drawn;
    for (const lod::SelectedPatch& d : desired.patches)
        for (PatchId p = d.id;; p = p.parent()) {
            drawn.push_back(p);
            if (p.level == 0)
                break;
        }
    (void)residency.update(drawn, 2);
    size_t detail_requests = 0;
    for (const StreamRequest& r : planner.plan(desired, {}, UploadBudget{}).requests) {
        EXPECT_FALSE(isDrawnChain(r.id));
        EXPECT_LT(r.priority, requestPriority(g, {g.finestLevel(), 0, 0}, 0.0));
        EXPECT_GT(r.priority, prefetchPriority(g, {0, 0, 0}, 1e9));
        ++detail_requests;
    }
    EXPECT_GE(detail_requests, desired.detail.size());
    EXPECT_GT(detailPriority(g, {2, 0, 0}, 0.0), detailPriority(g, {3, 0, 0}, 1e9));
    planner.finish(0);
}

// --- The executor's time budget (UploadTimeBudget), on a simulated clock -------------------

namespace {

// Frames of `work_ms` each (drawing, the host: everything but uploads), no uploads: the
// budget after `frames` of them.
double budgetAfterSteadyFrames(UploadTimeBudget& budget, double& now, double work_ms, int frames)
{
    double b = 0.0;
    for (int k = 0; k < frames; ++k) {
        b = budget.beginFrame(now);
        budget.endFrame(0.0);
        now += work_ms;
    }
    return b;
}

} // namespace

TEST(UploadTimeBudget, FollowsAFractionOfTheMedianFrameTimeBetweenItsFloorAndCeiling)
{
    const UploadTimeSettings settings{4.0, 0.25, 250.0};
    {
        UploadTimeBudget budget(settings);
        double now = 1000.0;
        // Until kMinFrames intervals are known: the floor, however slow the frames.
        for (int k = 0; k < UploadTimeBudget::kMinFrames; ++k) {
            EXPECT_EQ(budget.beginFrame(now), 4.0) << k;
            budget.endFrame(0.0);
            now += 200.0;
        }
        EXPECT_DOUBLE_EQ(budget.beginFrame(now), 50.0); // a quarter of 200 ms
        EXPECT_DOUBLE_EQ(budget.frameMs(), 200.0);
    }
    struct Case {
        double work_ms, budget_ms;
    };
    for (const Case c : {Case{16.0, 4.0},     // 60 Hz: a quarter is the 4 ms floor
                         Case{150.0, 37.5},   // llvmpipe
                         Case{4000.0, 250.0}, // the ceiling
                         Case{1.0, 4.0}}) {
        UploadTimeBudget budget(settings);
        double now = 0.0;
        EXPECT_DOUBLE_EQ(budgetAfterSteadyFrames(budget, now, c.work_ms, 40), c.budget_ms)
            << c.work_ms;
    }
    // Fraction 0: the fixed budget of old.
    UploadTimeBudget fixed({4.0, 0.0, 250.0});
    double now = 0.0;
    EXPECT_EQ(budgetAfterSteadyFrames(fixed, now, 150.0, 40), 4.0);
    // A ceiling below the floor: the floor wins.
    UploadTimeBudget low({10.0, 0.25, 2.0});
    now = 0.0;
    EXPECT_EQ(budgetAfterSteadyFrames(low, now, 150.0, 40), 10.0);
}

TEST(UploadTimeBudget, LeavesUploadsOutOfTheFrameTimeSoThatItDoesNotFeedOnItself)
{
    // Every frame spends its whole budget uploading: were uploads counted in the frame time,
    // the budget would climb to f·W / (1 − f) = 66.7 ms; without them it stays at f·W.
    UploadTimeBudget budget({4.0, 0.25, 250.0});
    double now = 0.0;
    for (int k = 0; k < 200; ++k) {
        const double b = budget.beginFrame(now);
        budget.endFrame(b);
        now += 200.0 + b;
    }
    EXPECT_DOUBLE_EQ(budget.beginFrame(now), 50.0);
}

TEST(UploadTimeBudget, ShrugsOffALongFrameAndAdaptsWithinHalfAWindow)
{
    UploadTimeBudget budget({4.0, 0.25, 1000.0});
    double now = 0.0;
    ASSERT_DOUBLE_EQ(budgetAfterSteadyFrames(budget, now, 100.0, 40), 25.0);
    // One 4 s frame (shader compilation, a window drag): the median does not move.
    budget.beginFrame(now);
    budget.endFrame(0.0);
    now += 4000.0;
    for (int k = 0; k < 5; ++k)
        EXPECT_DOUBLE_EQ(budgetAfterSteadyFrames(budget, now, 100.0, 1), 25.0) << k;
    // Frames become four times as slow: within half a window (plus one) the budget follows.
    int frames = 0;
    while (budgetAfterSteadyFrames(budget, now, 400.0, 1) != 100.0 && frames < 100)
        ++frames;
    EXPECT_LE(frames, UploadTimeBudget::kWindow / 2 + 1);
}

TEST(UploadTimeBudget, StartsTheFirstUploadAlwaysAndTheOthersWhileTheBudgetLasts)
{
    UploadTimeBudget budget({4.0, 0.25, 250.0});
    budget.beginFrame(0.0);
    EXPECT_TRUE(budget.mayStart(0, 1e6)); // streaming always progresses
    EXPECT_TRUE(budget.mayStart(1, 4.0));
    EXPECT_FALSE(budget.mayStart(1, 4.01));
}

TEST(UploadTimeBudget, RefusesSettingsOutsideTheirRangesAndIgnoresABadClock)
{
    const double nan = std::nan(""), inf = INFINITY;
    for (const UploadTimeSettings& bad :
         {UploadTimeSettings{0.0, 0.25, 250.0}, UploadTimeSettings{nan, 0.25, 250.0},
          UploadTimeSettings{4.0, 1.0, 250.0}, UploadTimeSettings{4.0, -0.1, 250.0},
          UploadTimeSettings{4.0, nan, 250.0}, UploadTimeSettings{4.0, 0.25, inf},
          UploadTimeSettings{4.0, 0.25, 0.0}})
        EXPECT_THROW(UploadTimeBudget{bad}, Error);
    try {
        UploadTimeBudget{UploadTimeSettings{4.0, 1.5, 250.0}};
        ADD_FAILURE() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("upload_frame_fraction"), std::string::npos)
            << e.what();
    }
    // A clock that steps back or is not finite adds no interval, however often (more than
    // the median could hide), and the next one runs from the last good start.
    UploadTimeBudget budget({4.0, 0.25, 250.0});
    double now = 0.0;
    ASSERT_DOUBLE_EQ(budgetAfterSteadyFrames(budget, now, 100.0, 40), 25.0);
    now -= 100.0; // the last frame's start
    for (int round = 0; round < UploadTimeBudget::kWindow; ++round)
        for (const double t : {nan, inf, now - 1e6, -inf}) {
            EXPECT_DOUBLE_EQ(budget.beginFrame(t), 25.0) << t;
            budget.endFrame(t);
        }
    EXPECT_DOUBLE_EQ(budget.beginFrame(now + 100.0), 25.0);
    EXPECT_DOUBLE_EQ(budget.frameMs(), 100.0);
}

// The case in miniature: frames of 150 ms (llvmpipe), each upload costing 10 ms,
// more than the whole fixed 4 ms budget. With the fixed budget only the one upload that
// always goes gets through per frame; the adaptive one lets a quarter of the frame's time
// through, so a static view reaches full detail in about a quarter of the frames, and no
// frame grows by more than a quarter plus one upload.
TEST(UploadTimeBudget, LetsAStaticViewReachFullDetailInAQuarterOfTheFramesWhenUploadsAreSlow)
{
    const lod::PatchQuadtree tree = syntheticTree(kGeometry);
    std::mt19937 rng(5);
    const lod::Selection desired = select(tree, randomCamera(rng), 512);
    const size_t n = desired.patches.size();
    ASSERT_GT(n, 60u);
    constexpr double kWorkMs = 150.0, kUploadMs = 10.0;
    for (const bool gpu : {false, true}) {
        struct Run {
            int frames = 0;          // to full detail
            double ms = 0.0;         // likewise, simulated
            double longest_ms = 0.0; // frame
            size_t uploads = 0;      // in all
        };
        auto run = [&](double fraction) {
            Simulation sim(kGeometry, 4096, gpu, 2);
            UploadTimeBudget budget({4.0, fraction, 250.0});
            const UploadBudget unlimited{size_t(1) << 40, 1 << 20}; // time binds, not bytes
            Run r;
            double now = 0.0;
            for (; r.frames < 2000 && !(sim.allResident(desired) && sim.waiting() == 0);
                 ++r.frames) {
                budget.beginFrame(now);
                // The executor's loop: how many uploads start within the budget.
                size_t fit = 0;
                while (budget.mayStart(fit, double(fit) * kUploadMs))
                    ++fit;
                const FrameReport f = sim.frame(desired, unlimited, fit);
                const double upload_ms = double(f.uploads) * kUploadMs;
                budget.endFrame(upload_ms);
                now += kWorkMs + upload_ms;
                r.ms = now;
                r.uploads += f.uploads;
                r.longest_ms = std::max(r.longest_ms, kWorkMs + upload_ms);
            }
            EXPECT_TRUE(sim.allResident(desired)) << "fraction " << fraction;
            return r;
        };
        const Run fixed = run(0.0), adaptive = run(0.25);
        // Fixed: one upload a frame, so at least as many frames as uploads.
        EXPECT_GE(size_t(fixed.frames), fixed.uploads) << "gpu " << gpu;
        EXPECT_GE(size_t(fixed.frames), n) << "gpu " << gpu;
        // Adaptive: 37.5 ms lets 4 uploads start (at 0, 10, 20, 30 ms); the floor's frames
        // until kMinFrames are known, and the streamer's delay, come on top.
        const size_t levels = size_t(kGeometry.levelCount());
        EXPECT_LE(size_t(adaptive.frames),
                  adaptive.uploads / 4 + UploadTimeBudget::kMinFrames + 2 * levels + 4)
            << "gpu " << gpu;
        EXPECT_LT(adaptive.ms, 0.4 * fixed.ms) << "gpu " << gpu;
        EXPECT_LE(adaptive.longest_ms, kWorkMs * 1.25 + kUploadMs) << "gpu " << gpu;
    }
}
