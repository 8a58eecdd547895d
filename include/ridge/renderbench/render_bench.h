#pragma once
// `ridge bench ARCHIVE`: a renderer flown along a deterministic camera path, headless, with
// per-frame figures (CPU ms by stage, GPU ms from timer queries, triangles, patches drawn and
// still streaming, uploads) and a summary. Not part of libridge (it plots with PLplot).
#include "ridge/lod/camera_path.h"
#include "ridge/render/terrain_renderer.h"

#include <string>
#include <vector>

namespace ridge::renderbench {

struct RenderBenchOptions {
    std::string scheme = "tess"; // a registered LOD scheme (render::lodSchemeNames())
    lod::CameraPathSettings path;
    int frames = 600;
    lod::Viewport viewport{1920, 1080};
    double epsilon_px = 2.0;
    double texel_px = 1.0; // render::RenderSettings::texel_px (0: off)
    bool cull = true;
    // Chunked: every patch's full grid instead of Ulrich's simplified chunks (simplified to
    // renderer.chunk_tolerance·Err(P)).
    bool grid_chunks = false;
    // Per frame, after its timing: the popping metric (two captures of this frame's camera,
    // with the previous frame's LOD state and with this one's; render/frame_measures.h).
    // Costly, and with streaming on the extra captures stream too: time a run without it.
    bool measure_popping = false;
    // The LOD rules (render::RenderSettings): defaults are ridge's, ε on every sample.
    lod::TessellationRule tessellation_rule = lod::TessellationRule::Conservative;
    bool side_on_bound = true;
    // Budgets, streaming (on by default) and decoding; the bench itself raises
    // max_resident_patches and measures with synchronous_stats.
    render::RendererOptions renderer = render::RendererOptions::streamingDefaults();

    // Throws ridge::Error naming the first field outside its range: frames in
    // [1, lod::CameraPathSettings::kMaxFrames], frame sides in [1, kMaxImageSide] of
    // render::HeadlessRenderOptions, epsilon_px (RenderSettings), path.validate(),
    // renderer.validate().
    void validate() const;
};

struct FrameRecord {
    double frame_ms = 0.0;  // wall time of draw() until the GPU finished it
    double select_ms = 0.0; // CPU: selection + culling
    double load_ms = 0.0;   // CPU: residency, uploads (streaming: requests and uploads only)
    double gpu_ms = 0.0;    // terrain pass, timer query
    uint64_t triangles = 0;
    int patches = 0;
    int missing = 0; // drawn by an ancestor while streaming
    int loaded = 0;
    int reconstructed = 0; // of `loaded`, on the GPU
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
};

struct RenderBenchReport {
    std::string archive;
    std::string gl_renderer;
    RenderBenchOptions options;
    std::vector<FrameRecord> frames;
    // Summary over all frames.
    double fps_min = 0, fps_median = 0, fps_max = 0;
    double frame_ms_p99 = 0;
    double frame_ms_max = 0;
    // Stalls: frames slower than twice the median (the streaming issue's target is none).
    int frames_over_twice_median = 0;
    double mtri_per_s = 0;      // triangles drawn / wall time
    int frames_missing = 0;     // frames that drew at least one patch by an ancestor
    double select_ms_max = 0;   // CPU selection + culling, worst frame
    size_t ram_cache_bytes = 0; // decoded-patch cache at the end
    uint64_t cache_misses = 0;  // patches decoded because the RAM cache did not have them
    double triangles_mean = 0;
    int frames_epsilon_raised = 0; // frames drawn coarser than asked (texture slots too few)
    uint64_t bytes_read = 0, bytes_decoded = 0, bytes_uploaded = 0; // all frames
    int reconstructed = 0;                                          // patches, on the GPU
    // Resident memory after the first tenth of the frames and at the end (a soak is flat
    // when the two agree once the RAM caches are full).
    double rss_early_mib = 0, rss_end_mib = 0;
    size_t hole_pixels = 0;     // all frames
    int frames_with_holes = 0;
    double popping_p99_px = -1, popping_max_px = -1; // −1: not measured
};

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
// Frame time per frame as a PNG (PLplot, pngcairo).
void writeRenderBenchPlot(const RenderBenchReport& report, const std::string& path);

} // namespace ridge::renderbench
