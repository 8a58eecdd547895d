#pragma once
// The resident set, executed (internal to ridge_render): which patches are in the
// texture-array slots, and getting them there. Synchronously (makeResident: the whole selection
// loaded and uploaded before the frame) or streaming (stream: the GL-free stream::UploadPlanner
// decides what to request, keep and upload; this uploads within the frame's budgets and draws
// the resident cover meanwhile). An upload reaches the shared texture arrays (PatchTextures:
// codes or a GPU reconstruction, λ, masks, then the normal maps) and every constructed scheme.
//
// Owns the slots' residency and texture arrays, the synchronous loader, the streamer and its
// planner, the decoded patches waiting for an upload, the upload time budget and the traffic
// counters behind FrameStats.
#include "patch_textures.h"
#include "scheme_plan.h"

#include "ridge/archive/archive_reader.h"
#include "ridge/lod/patch_quadtree.h"
#include "ridge/lod/patch_residency.h"
#include "ridge/lod/patch_selector.h"
#include "ridge/render/terrain_renderer.h"
#include "ridge/stream/patch_loader.h"
#include "ridge/stream/patch_streamer.h"
#include "ridge/stream/upload_planner.h"

#include <chrono>
#include <memory>
#include <unordered_map>
#include <unordered_set>
#include <vector>

namespace ridge::render {

class ResidentSet {
  public:
    // The codec whose patches streaming decodes on the GPU (its registered GPU decoder), or
    // null: a drawable scheme needs codes on the CPU, --cpu-decode, no streaming, or the codec
    // has no GPU half.
    static const HeightCodec* gpuDecodedCodec(const archive::ArchiveReader& reader,
                                              const RendererOptions& options,
                                              const SchemePlan& plan);
    // `slots` texture-array layers for the schemes of `plan`; the arguments must outlive this.
    // Streaming starts with start().
    ResidentSet(const archive::ArchiveReader& reader, const lod::PatchQuadtree& quadtree,
                const RendererOptions& options, int slots, const SchemePlan& plan);
    ~ResidentSet();
    ResidentSet(const ResidentSet&) = delete;
    ResidentSet& operator=(const ResidentSet&) = delete;

    // Uploads reach `schemes` (built over textures() and residency()) from now on; streaming,
    // the root is made resident: the last resort of every fallback. Once, before any frame.
    void start(Schemes& schemes);

    bool streaming() const { return streamer_ != nullptr; }
    PatchTextures& textures() { return *textures_; }
    const lod::PatchResidency& residency() const { return residency_; }
    // A patch decoded on this thread (the loader's cache or a decode now).
    std::shared_ptr<const stream::DecodedPatch> load(PatchId p) { return loader_.load(p); }

    // Synchronous: every patch of `selection` is resident when this returns.
    void makeResident(const lod::Selection& selection, FrameStats& stats);
    // Streaming: requests what is missing, uploads what arrived (within the per-frame budget)
    // and returns what to draw now: `selector`'s cover of `desired` (which it selected; for
    // the quadtree walk, missing patches replaced by resident ancestors). `settings`: the
    // selection's, for the prefetch (`selector` previews the camera ahead).
    lod::Selection stream(const lod::Selection& desired, lod::PatchSelector& selector,
                          const lod::Camera& camera, const lod::SelectionSettings& settings,
                          FrameStats& stats);
    // What to draw of `selection` from what is resident now (`selector`'s cover): no request,
    // no upload.
    lod::Selection cover(lod::Selection selection, lod::PatchSelector& selector) const;
    // The reads, decodes and cache traffic since the last call, into `stats`.
    void countTraffic(FrameStats& stats);

    // Streaming: see TerrainRenderer::waitForStreaming, streamingError, streamingCacheBytes.
    void waitIdle();
    bool waitIdleFor(double timeout_seconds);
    std::string error() const;
    size_t cacheBytes() const;
    // Since construction, either mode: patches decoded because the cache missed them, and
    // loads the cache served.
    uint64_t cacheMisses() const;
    uint64_t cacheHits() const;

  private:
    size_t uploadPatch(const stream::DecodedPatch& patch, int slot,
                       const std::unordered_set<int>& pending_slots = {});
    // What uploading `patch` will send, at most (the per-frame budget plans with it).
    size_t plannedUploadBytes(const stream::DecodedPatch& patch) const;
    void computeNormals(PatchId p, const std::unordered_set<int>& pending);
    // Whether the GPU decode of `p` reads its parent's slot.
    bool readsParent(PatchId p) const;
    // Base incremental: the steps to decode `patch` with for this frame's view (all of them
    // unless its codec is refinable and refinement is on), recorded for its slot.
    int stepsFor(const stream::DecodedPatch& patch, int slot);
    // Refines resident patches of `desired` decoded with fewer steps than the view now wants,
    // within the per-frame step budget (most visible first); returns whether any was.
    bool refine(const lod::Selection& desired, FrameStats& stats);

    // A slot's refinable patch: the bound of each step count (codes) and what it has.
    struct SlotSteps final : RefinablePayload {
        std::vector<double> bounds; // k = 0..full
        int steps = 0;
        int fullSteps() const override { return int(bounds.size()) - 1; }
        double stepBound(int k) const override { return bounds[size_t(k)]; }
    };

    const archive::ArchiveReader& reader_;
    const lod::PatchQuadtree& quadtree_;
    const RendererOptions& options_;
    Schemes* schemes_ = nullptr; // from start()
    lod::PatchResidency residency_;
    uint64_t frame_ = 0;  // residency's clock (synchronous frames)
    int gpu_decoded_ = 0; // patches decoded on the GPU since construction
    // Base incremental: per slot, its refinable patch's steps (empty bounds: none), and this
    // frame's desired patches by index (their Err_Scr decides the steps).
    std::vector<SlotSteps> slot_steps_;
    std::unordered_map<int64_t, lod::SelectedPatch> view_;
    double view_epsilon_px_ = 0.0;
    stream::PatchLoader loader_;
    std::unique_ptr<PatchTextures> textures_;
    // Streaming mode: decoded patches arrive from the streamer's workers and wait here for an
    // upload slot in a later frame.
    std::unique_ptr<stream::PatchStreamer> streamer_;
    std::vector<std::shared_ptr<const stream::DecodedPatch>> arrived_, waiting_;
    std::vector<stream::ArrivedPatch> arrived_descriptions_; // capacity kept across frames
    std::unique_ptr<stream::UploadPlanner> planner_;
    // The upload time budget follows the frame time, measured on this clock (ms since epoch).
    stream::UploadTimeBudget upload_time_;
    const std::chrono::steady_clock::time_point epoch_ = std::chrono::steady_clock::now();
    // Traffic counters at the end of the previous frame (FrameStats reports the difference).
    stream::StreamerStats last_streamer_stats_;
    stream::LoaderStats last_loader_stats_;
};

} // namespace ridge::render
