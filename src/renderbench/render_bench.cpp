// `ridge bench`'s run: a renderer flown along the camera path headless, each frame timed and
// measured (render_bench_report.cpp summarises and formats what it records).
#include "ridge/renderbench/render_bench.h"

#include "ridge/core/error.h"
#include "ridge/gpu/context.h"
#include "ridge/gpu/render_target.h"
#include "ridge/render/frame_measures.h"
#include "ridge/render/headless_render.h"
#include "ridge/render/scheme_options.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <unistd.h>

namespace ridge::renderbench {
namespace {

// Resident set size of this process in MiB (/proc/self/statm), 0 where unavailable.
double residentMib()
{
    std::FILE* f = std::fopen("/proc/self/statm", "r");
    if (!f)
        return 0.0;
    unsigned long pages = 0, resident = 0;
    const int got = std::fscanf(f, "%lu %lu", &pages, &resident);
    std::fclose(f);
    return got == 2 ? double(resident) * double(::sysconf(_SC_PAGESIZE)) / 1048576.0 : 0.0;
}

} // namespace

void RenderBenchOptions::validate() const
{
    checkParameter("frames", int64_t{frames}, 1, lod::CameraPathSettings::kMaxFrames);
    using render::HeadlessRenderOptions;
    checkParameter("frame width", int64_t{viewport.width}, 1, HeadlessRenderOptions::kMaxImageSide);
    checkParameter("frame height", int64_t{viewport.height}, 1,
                   HeadlessRenderOptions::kMaxImageSide);
    checkParameter("epsilon_px", epsilon_px, render::RenderSettings::kEpsilonPxRange);
    checkParameter("texel_px", texel_px, render::RenderSettings::kTexelPxRange);
    checkParameter("exaggeration", exaggeration, render::RenderSettings::kExaggerationRange);
    render::parseSchemeSpec(scheme, "scheme");
    path.validate();
    renderer.validate();
}

RenderBenchReport runRenderBench(const std::string& archive, const RenderBenchOptions& o)
{
    o.validate();
    RenderBenchReport report;
    report.archive = archive;
    report.options = o;
    const archive::ArchiveReader reader(archive);
    auto context = gpu::HeadlessContext::create();
    report.gl_renderer = context->rendererName();
    render::RendererOptions ro = o.renderer;
    ro.max_resident_patches = 2048;
    ro.synchronous_stats = true; // per-frame GPU time and triangles, measured
    ro.schemes = {o.scheme};
    render::TerrainRenderer renderer(reader, ro);
    const lod::PatchBounds& root = renderer.quadtree().bounds({0, 0, 0});
    // Vertical exaggeration: the path, clip planes and hole measure in the drawn space.
    const double k = o.exaggeration;
    const std::vector<lod::CameraPose> path = lod::makeCameraPath(
        renderer.quadtree().frame(), k * root.min_height, k * root.max_height,
        [&](double x, double y) { return renderer.groundHeight(x, y, k); }, o.path, o.frames);
    const gpu::RenderTarget target(o.viewport.width, o.viewport.height, 1);
    target.bind();
    render::RenderSettings settings;
    settings.scheme = render::parseSchemeSpec(o.scheme).scheme();
    settings.epsilon_px = o.epsilon_px;
    settings.texel_px = o.texel_px;
    settings.cull = o.cull;
    settings.tessellation_rule = o.tessellation_rule;
    settings.side_on_bound = o.side_on_bound;
    settings.exaggeration = k;
    std::optional<std::chrono::steady_clock::time_point> first_start; // of frame 0's draw
    for (const lod::CameraPose& pose : path) {
        const lod::Camera camera =
            renderer.cameraLookingAt(pose.position, pose.look_at, 60.0, o.viewport, k);
        target.bind();
        const auto t0 = std::chrono::steady_clock::now();
        if (!first_start)
            first_start = t0;
        // Synchronous stats wait for the frame's timer query: the GPU has finished the frame.
        const render::FrameStats s = renderer.draw(camera, settings);
        FrameRecord f;
        using Ms = std::chrono::duration<double, std::milli>;
        f.frame_ms = Ms(std::chrono::steady_clock::now() - t0).count();
        f.start_ms = Ms(t0 - *first_start).count();
        f.upload_budget_ms = s.upload_budget_ms;
        f.select_ms = s.cpu_select_ms;
        f.load_ms = s.cpu_load_ms;
        f.gpu_ms = std::isfinite(s.gpu_ms) ? s.gpu_ms : 0.0;
        f.triangles = s.triangles;
        f.patches = s.patches;
        f.missing = s.missing;
        f.detail = s.detail;
        f.detail_resident = s.detail_resident;
        f.fading = s.fading;
        f.loaded = s.loaded;
        f.reconstructed = s.reconstructed;
        f.refined = s.refined;
        f.refine_steps = s.refine_steps;
        f.under_refined = s.under_refined;
        f.level_shifts = s.level_shifts;
        f.levels_drawn = s.levels_drawn;
        f.levels_wanted = s.levels_wanted;
        f.samples_written = s.samples_written;
        f.epsilon_px = s.epsilon_px;
        f.coarser = s.coarser;
        f.cache_hits = s.cache_hits;
        f.cache_misses = s.cache_misses;
        f.bytes_read = s.bytes_read;
        f.bytes_decoded = s.bytes_decoded;
        f.bytes_uploaded = s.bytes_uploaded;
        // After the frame's timing: a /proc read and a lock, some microseconds.
        f.rss_mib = residentMib();
        f.ram_cache_mib = double(renderer.streamingCacheBytes()) / 1048576.0;
        const std::vector<float> depth = target.readDepth();
        std::vector<uint8_t> background(depth.size());
        for (size_t i = 0; i < depth.size(); ++i)
            background[i] = depth[i] == 0.f; // reverse-Z clears to 0: nothing drawn
        // A camera inside the slab (a low fly-over) is judged from the surface drawn under it:
        // the frame's own triangles, replayed (a capture; only for such frames).
        const lod::TerrainFrame& terrain = renderer.quadtree().frame();
        double under = std::numeric_limits<double>::quiet_NaN();
        const glm::dvec3 eye = camera.position();
        if (!terrain.onEllipsoid() && eye.z < k * root.max_height + 1.0)
            under = render::surfaceHeightUnder(renderer.lastFrameSurface(), terrain, eye.x, eye.y);
        const render::HoleReport holes = render::countHolePixels(
            background, camera, terrain, k * root.min_height, k * root.max_height, 4.0, under);
        f.hole_pixels = holes.hole_pixels;
        f.footprint_pixels = holes.footprint_pixels;
        if (o.measure_popping) { // this frame's surface against the previous frame's
            const render::PoppingReport popping = renderer.measureFramePopping(camera, settings);
            if (report.frames.size() > 0) {
                f.popping_px = popping.max_px;
                f.popping_sample_stride = popping.sample_stride;
            }
            target.bind();
        }
        report.frames.push_back(f);
    }
    if (!renderer.streamingError().empty())
        throw Error(renderer.streamingError());
    report.ram_cache_bytes = renderer.streamingCacheBytes();
    report.cache_misses = renderer.cacheMisses();
    summariseRenderBench(report);
    return report;
}

} // namespace ridge::renderbench
