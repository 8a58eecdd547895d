#pragma once
// `ridge bench ARCHIVE`: a renderer flown along a deterministic camera path, headless, with
// per-frame figures (CPU ms by stage, GPU ms from timer queries, triangles, patches drawn and
// still streaming, uploads) and a summary. Not part of libridge (it plots with PLplot).
#include "ridge/lod/camera_path.h"
#include "ridge/render/terrain_renderer.h"

#include <limits>
#include <string>
#include <vector>

namespace ridge::renderbench {

struct RenderBenchOptions {
    // The LOD scheme and its own options: a spec "NAME[,KEY=VALUE...]" of a registered scheme
    // (render::RendererOptions::schemes; ridge/render/scheme_options.h), as --lod takes it.
    std::string scheme = render::defaultLodScheme();
    lod::CameraPathSettings path;
    int frames = 600;
    lod::Viewport viewport{1920, 1080};
    double epsilon_px = 2.0;
    double texel_px = 1.0; // render::RenderSettings::texel_px (0: off)
    bool cull = true;
    // Vertical exaggeration (render::RenderSettings::exaggeration): the path flies over the
    // exaggerated terrain.
    double exaggeration = 1.0;
    // `--popping`. Per frame, after its timing: the popping metric (this frame's camera drawn
    // with the previous frame's LOD state and with this one's, of what is resident;
    // render/frame_measures.h) by one capture a frame, compared on the GPU on a plane frame
    // (TerrainRenderer::measureFramePopping). It adds to the time between frames (and so to
    // the time to full detail): time a run without it.
    bool measure_popping = false;
    // The LOD rules (render::RenderSettings): defaults are ridge's, ε on every sample.
    lod::TessellationRule tessellation_rule = lod::TessellationRule::Conservative;
    bool side_on_bound = true;
    // Budgets, streaming (on by default) and decoding; the bench itself raises
    // max_resident_patches and measures with synchronous_stats.
    render::RendererOptions renderer = render::RendererOptions::streamingDefaults();

    // Throws ridge::Error naming the first field outside its range: frames in
    // [1, lod::CameraPathSettings::kMaxFrames], frame sides in [1, kMaxImageSide] of
    // render::HeadlessRenderOptions, epsilon_px (RenderSettings), a scheme spec that does not
    // parse (render::parseSchemeSpec), path.validate(), renderer.validate().
    void validate() const;
};

struct FrameRecord {
    double start_ms = 0.0;         // wall time from the first frame's start to this frame's start
    double frame_ms = 0.0;         // wall time of draw() until the GPU finished it
    double select_ms = 0.0;        // CPU: selection + culling
    double load_ms = 0.0;          // CPU: residency, uploads (streaming: requests and uploads only)
    double gpu_ms = 0.0;           // terrain pass, timer query
    double upload_budget_ms = 0.0; // streaming: the frame's upload time budget (adaptive)
    uint64_t triangles = 0;
    int patches = 0;
    int missing = 0;                     // drawn by an ancestor while streaming
    int detail = 0, detail_resident = 0; // texture detail wanted, and resident (FrameStats)
    int fading = 0;                      // arrivals fading in over their ancestor
    int loaded = 0;
    int reconstructed = 0; // of `loaded`, on the GPU
    int refined = 0;       // resident patches refined in place (Base incremental)
    int refine_steps = 0;  // iterations that took
    int under_refined = 0; // drawn with fewer iterations than the view wants (budget spent)
    // Level windows (clipmaps, FrameStats): shifts, levels drawn and wanted, samples written.
    int level_shifts = 0, levels_drawn = 0, levels_wanted = 0;
    uint64_t samples_written = 0;
    double epsilon_px = 0; // ε met
    bool coarser = false;  // drawn above the requested ε: the view needed more slots
    int cache_hits = 0, cache_misses = 0; // decoded-patch cache
    uint64_t bytes_read = 0, bytes_decoded = 0, bytes_uploaded = 0;
    double rss_mib = 0;       // the process's resident memory after the frame (Linux)
    double ram_cache_mib = 0; // the streamer's RAM caches, likewise
    // Measured on the frame itself, after its timing (render/frame_measures.h).
    size_t hole_pixels = 0;      // background inside the terrain's footprint
    size_t footprint_pixels = 0; // pixels whose ray must hit the terrain
    double popping_px = -1.0;    // LOD changes alone, pixels (−1: not measured)
    // Popping compared every this many samples along each axis (1: all; the GPU measure
    // thins a window past its texture limit; 0: not measured).
    int popping_sample_stride = 0;

    // At full detail: what the scheme draws at the requested ε — no patch drawn by an
    // ancestor while streaming, ε not raised for want of texture slots. Every other frame
    // is drawn coarser, and its time is not the scheme's.
    // A clipmap drawing fewer levels than the view wants (strips waiting) is coarser too.
    bool fullDetail() const { return missing == 0 && !coarser && levels_drawn == levels_wanted; }
};

// A distribution over some frames: how many it rests on and only the percentiles they can
// support. Percentiles are nearest-rank (the ⌈p·n⌉-th smallest); pXX is claimed only when at
// least one frame lies above it (n ≥ 1 / (1 − p): p90 from 10 frames, p99 from 100), so with
// 60 frames there is no p99 (it would be the worst frame, often the warm-up). NaN: not
// claimed (no frames, or too few).
struct FrameStatistics {
    int count = 0;
    double median = std::numeric_limits<double>::quiet_NaN();
    double p90 = std::numeric_limits<double>::quiet_NaN();
    double p99 = std::numeric_limits<double>::quiet_NaN();
    double max = std::numeric_limits<double>::quiet_NaN();
};
// Non-finite values are left out.
FrameStatistics frameStatistics(std::vector<double> values);
// Frames a percentile p in (0, 1) needs before it is claimed: ⌈1 / (1 − p)⌉.
int framesForPercentile(double p);

// How long the view took to reach full detail after the camera started or jumped.
struct TimeToFullDetail {
    int frame = 0;         // where the camera started (0) or teleported
    bool teleport = false; // false: the start of the run
    // Frames from `frame` to the first frame at full detail, counting both; −1: not reached
    // before the next teleport or the end of the run.
    int frames = -1;
    // Wall time from the start of `frame` to the end of that first frame at full detail
    // (draws and the bench's own per-frame measurements between them); NaN: not reached.
    double ms = std::numeric_limits<double>::quiet_NaN();
    // Not reached: the frames and wall time the segment lasted without reaching it.
    int segment_frames = 0;
    double segment_ms = 0.0;
};

struct RenderBenchReport {
    std::string archive;
    std::string gl_renderer;
    RenderBenchOptions options;
    std::vector<FrameRecord> frames;

    // Full detail against coarser (FrameRecord::fullDetail).
    int frames_full_detail = 0;
    int frames_coarser = 0;        // not at full detail, for either reason below
    int frames_missing = 0;        // frames that drew at least one patch by an ancestor
    int frames_epsilon_raised = 0; // frames drawn at a raised ε (texture slots too few)
    // After the start (first) and after each teleport of the `teleport` path.
    std::vector<TimeToFullDetail> time_to_full_detail;
    // The scheme's frame time: frames at full detail, the warm-up frame (frame 0: shader
    // compilation, first allocations and loads) left out. Frames drawn coarser apart, same
    // rule; the warm-up frame alone.
    FrameStatistics full_detail_ms, coarser_ms;
    double warmup_ms = 0.0;
    FrameStatistics upload_budget_ms; // streamed frames' time budgets

    // Summary over all frames, warm-up and streaming included (the fractal-rings paper's
    // table reads these; every frame there is loaded in full first).
    double fps_min = 0, fps_median = 0, fps_max = 0;
    FrameStatistics all_ms;
    // Stalls: frames slower than twice the median of all frames (the streaming issue's
    // target is none).
    int frames_over_twice_median = 0;
    double mtri_per_s = 0;      // triangles drawn / wall time
    double select_ms_max = 0;   // CPU selection + culling, worst frame
    size_t ram_cache_bytes = 0; // decoded-patch cache at the end
    uint64_t cache_misses = 0;  // patches decoded because the RAM cache did not have them
    double triangles_mean = 0;
    uint64_t bytes_read = 0, bytes_decoded = 0, bytes_uploaded = 0; // all frames
    int reconstructed = 0;                                          // patches, on the GPU
    int refined = 0, refine_steps = 0; // Base incremental: refinements in place, their steps
    int frames_under_refined = 0;      // frames with a patch drawn short of its iterations
    // Level windows (clipmaps): shifts a frame on average, samples written in all, frames
    // that drew fewer levels than the view wants.
    double level_shifts_per_frame = 0;
    uint64_t samples_written = 0;
    int frames_levels_waiting = 0;
    // Resident memory after the first tenth of the frames and at the end (a soak is flat
    // when the two agree once the RAM caches are full).
    double rss_early_mib = 0, rss_end_mib = 0;
    size_t hole_pixels = 0; // all frames
    int frames_with_holes = 0;
    FrameStatistics popping_px;    // frames measured with --popping (count 0: not measured)
    int popping_sample_stride = 0; // the largest of the frames' (0: not measured)
};

// The frames where the camera starts or jumps: 0, and with the `teleport` path every
// path.teleport_every-th frame.
std::vector<int> cameraJumpFrames(const RenderBenchOptions& options);
// Fills the summary fields of `report` from its frames and options (runRenderBench does);
// summarising twice gives the same report.
void summariseRenderBench(RenderBenchReport& report);

// Throws ridge::Error naming the archive or path file on bad input; options are validated
// before the archive is opened.
RenderBenchReport runRenderBench(const std::string& archive, const RenderBenchOptions& options);
std::string formatRenderBenchSummary(const RenderBenchReport& report);
// The fractal-rings paper's Table 1, one row per report: approach, FPS min / max / median,
// cache misses, mean triangles.
std::string formatRenderBenchTable(const std::vector<RenderBenchReport>& reports);
// Every frame's figures and the summary as a JSON document (ends with a newline).
std::string formatRenderBenchJson(const RenderBenchReport& report);
// Writes formatRenderBenchJson to `path` atomically. Throws ridge::Error naming the path.
void writeRenderBenchJson(const RenderBenchReport& report, const std::string& path);
// The plot's three title lines: the scheme, archive, frame size, ε and path; frames at full
// detail, the scheme's median frame time over them and time to full detail; the legend and
// the GL renderer.
std::vector<std::string> renderBenchPlotTitles(const RenderBenchReport& report);
// Frame time per frame as a PNG (PLplot, pngcairo); frames at full detail marked.
void writeRenderBenchPlot(const RenderBenchReport& report, const std::string& path);

} // namespace ridge::renderbench
