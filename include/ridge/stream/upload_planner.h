#pragma once
// The streaming policy of the renderer, without GL: each frame, what to ask the streamer for,
// which arrived patches to upload into which texture-array slot within the upload budget,
// which to keep waiting, and what to draw meanwhile (the resident cover of the selection).
// The GL layer executes the plan:
//
//     time_budget.beginFrame(now);
//     const StreamPlan& plan = planner.plan(desired, arrived, budget);
//     for (const StreamRequest& r : plan.requests) streamer.request(r.id, r.priority);
//     size_t done = 0;
//     for (; done < plan.uploads.size() && time_budget.mayStart(done, elapsed); ++done)
//         upload(arrived patch plan.uploads[done].handle, into plan.uploads[done].slot);
//     time_budget.endFrame(elapsed);
//     const StreamOutcome& outcome = planner.finish(done); // releases what was not written
//     keep the arrived patches of outcome.waiting; draw outcome.drawn.
//
// The policy (the hardware-tessellation paper's streaming, with the fractal-rings paper's LRU
// tile cache, lod::PatchResidency):
//   - requests: the selection, coarse before fine, then by its rank (screen-space error for
//     the quadtree walk, the scheme's own order for a scheme's selector); also every
//     ancestor up to the finest resident one, ahead of it (one request round for the whole
//     chain: GPU reconstruction needs the parent, and the view refines level by level
//     instead of staying at the root until the whole selection arrived); not what is
//     resident or arrived already;
//   - then the selection's texture detail (lod::Selection::detail) and its chains, below
//     every drawn patch and above every prefetch, and only in frames where every drawn
//     patch is resident (so that no worker is busy with detail while a drawn patch waits);
//   - kept resident: the root, what is drawn now (the selector's cover of the selection:
//     lod::residentCover for the quadtree walk, the scheme's own rule otherwise) and
//     the resident parents of arrived patches waiting for GPU reconstruction; then, as far
//     as the slots have room after the drawn patches' uploads, what else of their chains is
//     resident, and then resident texture detail;
//   - uploads: arrived patches still wanted, coarse first (a parent is written before its
//     children), within the byte and count budgets (at least one when one is ready) and the
//     free slots, and (the executor's part) within a time budget that follows the frame time
//     (UploadTimeBudget); a patch whose GPU decoder reads its parent only once the parent is
//     resident and kept, or uploaded earlier in the same plan; texture detail's after all
//     of the drawn patches', in what they left of the budgets and slots.
//
// No allocation per frame once the vectors have grown to the frame's sizes: members are
// cleared, not rebuilt, and per-frame sets are FrameKeyMaps (generation-stamped open
// addressing), not node-based hash sets or arrays over every patch of the archive.
// Not thread-safe: one planner per render thread.
#include "ridge/core/parameter_check.h"
#include "ridge/lod/patch_quadtree.h"
#include "ridge/lod/patch_residency.h"
#include "ridge/lod/patch_selector.h"
#include "ridge/lod/resident_cover.h"
#include "ridge/stream/frame_key_map.h"

#include <array>
#include <cstddef>
#include <functional>
#include <optional>
#include <span>
#include <vector>

namespace ridge::stream {

// A decoded patch waiting on the CPU for its upload, as the planner sees it.
struct ArrivedPatch {
    PatchId id;
    size_t upload_bytes = 0; // what uploading it sends, at most
    // Its GPU decoder reads the parent's resident codes (GpuDecoding::parent_resident).
    bool needs_parent_resident = false;
    size_t handle = 0; // the caller's: where the patch is in its list
};

// PatchStreamer::request(id, priority): a larger priority is served first.
struct StreamRequest {
    PatchId id;
    double priority = 0.0;
};

// Per frame. Time is the executor's: it may stop early (UploadPlanner::finish).
struct UploadBudget {
    size_t bytes = size_t(8) << 20;
    int count = 16;
};

// The executor's time budget: how long one frame may spend uploading before the rest of the
// plan waits for the next frame (RendererOptions::upload_budget_ms, upload_frame_fraction,
// upload_budget_max_ms).
//
// Why it follows the frame time: a fixed budget is sized for one frame rate. 4 ms is a
// quarter of a 60 Hz frame, but in a 150 ms frame (llvmpipe, or a heavy scheme on a weak GPU)
// it is under 3 %, and where one upload costs more than the whole budget (a 129² GPU
// reconstruction with its normal passes takes 10–20 ms on llvmpipe) only the one upload that
// always goes gets through: a view of 150 missing patches then takes 150 frames — a minute —
// to reach full detail. Streaming should cost the same share of every frame instead. So:
//
//     budget = max(floor_ms, min(frame_fraction · T, ceiling_ms))
//
// where T is the median, over the last kWindow frames, of the time between the starts of
// successive frames less the time those frames spent uploading (the frame's own work: drawing,
// the host's work, waiting for vsync). Uploads are left out of T so that the budget does not
// feed on itself: spending f·T on uploads makes a frame at most 1 + f times as long as it
// would be without streaming (plus one upload's overrun), whatever the frame rate. Where
// frames are short against one upload (a coarse view drawing the root alone, with uploads
// decoded on the CPU), f·T stays below one upload and one patch a frame goes, as with the
// fixed budget; the gain is where frames are long (docs/PERF.md, issue 22). The median, not a
// running mean: one long frame (shader compilation on the first frame, a window drag, an idle host)
// does not swing the budget, and it adapts within half a window to a real change. Until kMinFrames
// intervals are known, the floor. The floor is the fixed budget (so a fast GPU behaves as
// before: at 60 Hz a quarter of the frame is the 4 ms floor); the ceiling (a quarter of a
// second) bounds the stall one frame may take for uploads however slow the frames are.
// frame_fraction 0: the fixed budget alone.
//
// Time is the caller's clock in milliseconds (steady); nothing here reads a clock, so the
// policy is tested with simulated frames. No allocation. Not thread-safe.
struct UploadTimeSettings {
    // The ranges UploadTimeBudget (and RendererOptions::validate) enforce.
    static constexpr ValueRange kFloorMsRange = ValueRange::openClosed(0.0, 1e9);
    static constexpr ValueRange kFrameFractionRange = ValueRange::closedOpen(0.0, 1.0);
    static constexpr ValueRange kCeilingMsRange = ValueRange::openClosed(0.0, 1e9);

    double floor_ms = 4.0;        // the fixed budget; never less
    double frame_fraction = 0.25; // of the recent frame time (0: the floor alone)
    double ceiling_ms = 250.0;    // never more (below the floor: the floor wins)
};

class UploadTimeBudget {
  public:
    static constexpr int kWindow = 16;   // frames whose time the budget follows
    static constexpr int kMinFrames = 3; // intervals known before it adapts

    // Throws ridge::Error naming the first setting outside its range (NaN included).
    explicit UploadTimeBudget(const UploadTimeSettings& settings = {});

    // A frame starts at `now_ms`: records the interval since the previous frame's start
    // (less that frame's uploads) and returns this frame's budget. A clock that runs
    // backwards or is not finite adds no interval.
    double beginFrame(double now_ms);
    // Whether the upload after the first `done` may start, `elapsed_ms` after this frame's
    // uploads began: the first one always (streaming always progresses), the others while
    // the budget lasts. An upload started inside the budget may overrun it by its own cost.
    bool mayStart(size_t done, double elapsed_ms) const
    {
        return done == 0 || elapsed_ms <= budget_ms_;
    }
    // This frame's uploads took `upload_ms` (0 when there were none).
    void endFrame(double upload_ms);

    double budgetMs() const { return budget_ms_; } // this frame's
    // T above: the median frame time without uploads, ms (0 until kMinFrames are known).
    double frameMs() const { return frame_ms_; }
    const UploadTimeSettings& settings() const { return settings_; }

  private:
    UploadTimeSettings settings_;
    std::array<double, kWindow> window_{}; // frame times without uploads, a ring
    int count_ = 0;                        // valid entries of window_
    int next_ = 0;                         // where the next one goes
    bool started_ = false;                 // a previous frame start is known
    double last_start_ms_ = 0.0;
    double last_upload_ms_ = 0.0; // the previous frame's, taken out of its interval
    double frame_ms_ = 0.0;
    double budget_ms_ = 0.0;
};

struct PlannedUpload {
    PatchId id;
    int slot = 0; // the texture-array slot to write, from lod::PatchResidency::update
    size_t upload_bytes = 0;
    bool needs_parent_resident = false;
    size_t handle = 0; // ArrivedPatch::handle
};

// What plan() decides; valid until the next plan().
struct StreamPlan {
    std::vector<StreamRequest> requests; // for PatchStreamer::request, in any order
    // Coarse first: execute in this order, so that a parent is written before its children.
    std::vector<PlannedUpload> uploads;
    // Handles of arrived patches to let go: no longer wanted, already resident or listed
    // twice (the streamer's RAM cache still has them for a later request).
    std::vector<size_t> dropped;
};

// What finish() settles; valid until the next plan().
struct StreamOutcome {
    lod::Selection drawn;        // the selector's cover of the desired selection: draw this
    std::vector<size_t> waiting; // handles of arrived patches to offer again next frame
    int missing = 0;             // desired patches drawn by an ancestor
    int uploaded = 0;            // uploads done
};

// Coarse before fine, then by rank (SelectedPatch::rank, Err_Scr for the quadtree walk):
// 10^6 per level above the finest, the rank below it.
double requestPriority(const PyramidGeometry& geometry, PatchId p, double rank);
// Below every requestPriority and above every prefetchPriority of the geometry, coarse first:
// texture detail (lod::Selection::detail).
double detailPriority(const PyramidGeometry& geometry, PatchId p, double rank);
// Below every requestPriority of the geometry: for what a later frame will need.
double prefetchPriority(const PyramidGeometry& geometry, PatchId p, double rank);

// `camera` moved `frames` frames ahead at `velocity` (terrain-frame metres per frame), looking
// the same way, within kCameraCoordinateRange however far that extrapolates; nothing when
// `frames` <= 0 or the camera stands still.
std::optional<lod::Camera> extrapolatedCamera(const lod::Camera& camera, glm::dvec3 velocity,
                                              int frames);

class UploadPlanner {
  public:
    // `residency` is the caller's (it also maps patches to slots when drawing) and must
    // outlive the planner; its root patch must be resident before the first plan().
    // Whether the streamer delivers residuals (GPU reconstruction) or codes, ancestor chains
    // are requested alike: what an arrived patch needs is in ArrivedPatch.
    UploadPlanner(const PyramidGeometry& geometry, lod::PatchResidency& residency);
    // Pinned: is_resident_ captures `this`.
    UploadPlanner(const UploadPlanner&) = delete;
    UploadPlanner& operator=(const UploadPlanner&) = delete;

    // Plans a frame: `desired` is this frame's selection (at most residency.capacity()
    // patches), `arrived` every decoded patch not yet uploaded (last frame's waiting ones and
    // what the streamer delivered since). `selector` made `desired` and decides what is
    // drawn (its cover) until finish(); it must outlive the plan. Without one, the resident
    // cover of the quadtree walk. Assigns the uploads their slots at once. Throws
    // ridge::Error when the root is not resident or the last plan was not finished.
    const StreamPlan& plan(const lod::Selection& desired, std::span<const ArrivedPatch> arrived,
                           const UploadBudget& budget, lod::PatchSelector* selector = nullptr);
    // Appends to the current plan's requests, below all of them, what `selector` previews
    // for `camera` (`settings`) `frames` frames ahead at its velocity since the previous call
    // (none the first time), less what is resident or requested already. Between plan() and
    // finish().
    void prefetch(const lod::PatchSelector& selector, const lod::Camera& camera, int frames,
                  const lod::SelectionSettings& settings);
    // The same for the quadtree walk.
    void prefetch(const lod::PatchQuadtree& quadtree, const lod::Camera& camera, int frames,
                  const lod::SelectionSettings& settings)
    {
        prefetch(lod::QuadtreeSelector(quadtree), camera, frames, settings);
    }
    // Ends the frame after the first `done` uploads of the plan were written: the slots of
    // the others are released and their patches wait for a later frame. Call it also when an
    // upload throws (with the index of the failed one), before rethrowing.
    const StreamOutcome& finish(size_t done);

  private:
    bool resident(PatchId p) const { return residency_.slotOf(p) >= 0; }
    void coverDesired();
    // wanted_'s values: why a patch is wanted this frame.
    static constexpr char kDrawn = 1;  // the selection's drawn patches and their chains
    static constexpr char kDetail = 2; // its texture detail (Selection::detail) and chains
    bool want(PatchId p, double priority, char kind = kDrawn);
    void collectWanted(const lod::Selection& desired);
    void wantWithChains(const std::vector<lod::SelectedPatch>& patches,
                        double (*priority)(const PyramidGeometry&, PatchId, double), char kind);
    void need(PatchId p);
    void sortArrived(std::span<const ArrivedPatch> arrived);
    bool hasArrived(PatchId p, std::span<const ArrivedPatch> arrived) const;
    void keepParentsOfWaiting(std::span<const ArrivedPatch> arrived);
    bool parentReady(const ArrivedPatch& a) const;
    void keepWantedChains();
    void keepDetail(const lod::Selection& desired);
    void chooseUploads(std::span<const ArrivedPatch> arrived, const UploadBudget& budget,
                       char kind);
    void assignSlots();

    PyramidGeometry geometry_;
    lod::PatchResidency& residency_;
    std::function<bool(PatchId)> is_resident_; // for lod::residentCover, built once

    StreamPlan plan_;
    StreamOutcome outcome_;
    bool open_ = false;                      // plan() done, finish() not yet
    lod::Selection desired_;                 // this frame's, for the cover drawn after the uploads
    lod::PatchSelector* selector_ = nullptr; // this frame's (null: residentCover)
    lod::ResidentCover cover_;               // scratch
    lod::Selection future_;                  // prefetch's preview, capacity kept
    FrameKeyMap<char> wanted_; // patch index -> wanted this frame (requested unless resident)
    std::vector<StreamRequest> wanted_list_;
    FrameKeyMap<char> needed_; // patch index -> kept resident this frame
    std::vector<PatchId> needed_list_;
    FrameKeyMap<char> uploading_; // patch index -> in plan_.uploads
    std::vector<size_t> order_;   // positions in `arrived`, coarse first

    glm::dvec3 last_camera_{0.0}; // prefetch: the camera's velocity
    bool has_last_camera_ = false;
};

} // namespace ridge::stream
