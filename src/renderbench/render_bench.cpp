#include "ridge/renderbench/render_bench.h"

#include "ridge/core/json_text.h"
#include "ridge/render/frame_measures.h"

#include "ridge/core/atomic_output.h"
#include "ridge/core/error.h"
#include "ridge/core/file_identity.h"
#include "ridge/gpu/context.h"
#include "ridge/gpu/render_target.h"
#include "ridge/render/headless_render.h"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <cstdio>
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

double percentile(std::vector<double> v, double p)
{
    if (v.empty())
        return 0.0;
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, size_t(std::ceil(p * double(v.size() - 1))))];
}

void summarise(RenderBenchReport& r)
{
    std::vector<double> ms;
    double total_ms = 0.0, triangles = 0.0;
    for (const FrameRecord& f : r.frames) {
        ms.push_back(f.frame_ms);
        total_ms += f.frame_ms;
        triangles += double(f.triangles);
        r.frames_missing += f.missing > 0;
        r.select_ms_max = std::max(r.select_ms_max, f.select_ms);
        r.frames_epsilon_raised += f.coarser;
        r.hole_pixels += f.hole_pixels;
        r.frames_with_holes += f.hole_pixels > 0;
        r.bytes_read += f.bytes_read;
        r.bytes_decoded += f.bytes_decoded;
        r.bytes_uploaded += f.bytes_uploaded;
        r.reconstructed += f.reconstructed;
    }
    if (ms.empty())
        return;
    auto fps = [](double frame_ms) { return frame_ms > 0.0 ? 1000.0 / frame_ms : 0.0; };
    r.fps_min = fps(percentile(ms, 1.0));
    r.fps_median = fps(percentile(ms, 0.5));
    r.fps_max = fps(percentile(ms, 0.0));
    r.frame_ms_max = percentile(ms, 1.0);
    r.rss_early_mib = r.frames[r.frames.size() / 10].rss_mib;
    r.rss_end_mib = r.frames.back().rss_mib;
    const double median = percentile(ms, 0.5);
    r.frames_over_twice_median =
        int(std::count_if(ms.begin(), ms.end(), [&](double m) { return m > 2.0 * median; }));
    r.frame_ms_p99 = percentile(ms, 0.99);
    std::vector<double> popping;
    for (const FrameRecord& f : r.frames)
        if (f.popping_px >= 0)
            popping.push_back(f.popping_px);
    if (!popping.empty()) {
        r.popping_p99_px = percentile(popping, 0.99);
        r.popping_max_px = percentile(popping, 1.0);
    }
    r.mtri_per_s = total_ms > 0.0 ? triangles / (total_ms * 1e3) : 0.0;
    r.triangles_mean = triangles / double(r.frames.size());
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
    ro.chunk_meshes = !o.grid_chunks; // what "chunked" draws
    ro.schemes = {o.scheme};
    render::TerrainRenderer renderer(reader, ro);
    const lod::PatchBounds& root = renderer.quadtree().bounds({0, 0, 0});
    const std::vector<lod::CameraPose> path = lod::makeCameraPath(
        renderer.quadtree().frame(), root.min_height, root.max_height,
        [&](double x, double y) { return renderer.groundHeight(x, y); }, o.path, o.frames);
    const gpu::RenderTarget target(o.viewport.width, o.viewport.height, 1);
    target.bind();
    render::RenderSettings settings;
    settings.scheme = o.scheme;
    settings.epsilon_px = o.epsilon_px;
    settings.texel_px = o.texel_px;
    settings.cull = o.cull;
    settings.tessellation_rule = o.tessellation_rule;
    settings.side_on_bound = o.side_on_bound;
    std::optional<lod::Camera> previous; // the popping metric's previous LOD state
    for (const lod::CameraPose& pose : path) {
        double near_m = 1.0, far_m = 1e6;
        renderer.clipPlanesFor(pose.position, near_m, far_m);
        const lod::Camera camera(pose.position, pose.look_at, 60.0, o.viewport, near_m, far_m);
        // The popping metric's first half, before this frame changes anything: this camera
        // drawn with the previous frame's LOD state (its LOD camera and resident patches).
        render::SampleHeights before;
        const lod::TerrainFrame& frame = renderer.quadtree().frame();
        if (o.measure_popping && previous)
            before = render::surfaceHeightsAtSamples(
                renderer.capture(camera, settings, &*previous, true), frame);
        target.bind();
        const auto t0 = std::chrono::steady_clock::now();
        // Synchronous stats wait for the frame's timer query: the GPU has finished the frame.
        const render::FrameStats s = renderer.draw(camera, settings);
        FrameRecord f;
        f.frame_ms =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                .count();
        f.select_ms = s.cpu_select_ms;
        f.load_ms = s.cpu_load_ms;
        f.gpu_ms = std::isfinite(s.gpu_ms) ? s.gpu_ms : 0.0;
        f.triangles = s.triangles;
        f.patches = s.patches;
        f.missing = s.missing;
        f.loaded = s.loaded;
        f.reconstructed = s.reconstructed;
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
        const render::HoleReport holes = render::countHolePixels(
            background, camera, renderer.quadtree().frame(), root.min_height, root.max_height);
        f.hole_pixels = holes.hole_pixels;
        f.footprint_pixels = holes.footprint_pixels;
        if (!before.z.empty()) { // ... and with this frame's, as drawn
            const render::SampleHeights after = render::surfaceHeightsAtSamples(
                renderer.capture(camera, settings, nullptr, true), frame);
            f.popping_px = render::measurePopping(before, after, frame, camera).max_px;
            target.bind();
        }
        previous = camera;
        report.frames.push_back(f);
    }
    if (!renderer.streamingError().empty())
        throw Error(renderer.streamingError());
    report.ram_cache_bytes = renderer.streamingCacheBytes();
    report.cache_misses = renderer.cacheMisses();
    summarise(report);
    return report;
}

std::string formatRenderBenchSummary(const RenderBenchReport& r)
{
    auto mib = [](uint64_t bytes) { return double(bytes) / (1024.0 * 1024.0); };
    return fmt::format(
        "{}: {} renderer, path {}, {} frames at {}x{}, ε {} px, culling {}, {}\n"
        "  fps min / median / max   {:.1f} / {:.1f} / {:.1f}\n"
        "  frame time p99 / max     {:.2f} / {:.2f} ms\n"
        "  frames over 2x median    {}\n"
        "  triangles                {:.2f} Mtri/s\n"
        "  CPU selection, worst     {:.3f} ms\n"
        "  frames still streaming   {} of {}\n"
        "  frames drawn coarser     {} (more patches in view than texture slots)\n"
        "  RAM caches at the end    {:.1f} MiB\n"
        "  resident memory          {:.1f} MiB after {} frames, {:.1f} MiB at the end\n"
        "  read / decoded / upload  {:.1f} / {:.1f} / {:.1f} MiB ({} patches "
        "reconstructed on the GPU)\n"
        "  hole pixels              {} in {} frames\n"
        "  popping p99 / max        {}\n",
        r.archive, r.options.scheme, r.options.path.kind, r.frames.size(),
        r.options.viewport.width, r.options.viewport.height, r.options.epsilon_px,
        r.options.cull ? "on" : "off", r.gl_renderer, r.fps_min, r.fps_median, r.fps_max,
        r.frame_ms_p99, r.frame_ms_max, r.frames_over_twice_median, r.mtri_per_s, r.select_ms_max,
        r.frames_missing, r.frames.size(), r.frames_epsilon_raised, mib(r.ram_cache_bytes),
        r.rss_early_mib, r.frames.size() / 10 + 1, r.rss_end_mib, mib(r.bytes_read),
        mib(r.bytes_decoded), mib(r.bytes_uploaded), r.reconstructed, r.hole_pixels,
        r.frames_with_holes,
        r.popping_max_px < 0
            ? std::string("not measured (measure_popping)")
            : fmt::format("{:.3f} / {:.3f} px", r.popping_p99_px, r.popping_max_px));
}

std::string formatRenderBenchTable(const std::vector<RenderBenchReport>& reports)
{
    std::string out =
        fmt::format("{:<38} {:>9} {:>9} {:>9} {:>11} {:>12} {:>8}\n", "approach", "FPS min",
                    "FPS max", "FPS med", "cache miss", "triangles", "coarser");
    for (const RenderBenchReport& r : reports) {
        const std::string name =
            fmt::format("{}{}{}", r.options.scheme, r.options.grid_chunks ? ", grid chunks" : "",
                        r.options.cull ? "" : " without frustum");
        out += fmt::format("{:<38} {:>9.1f} {:>9.1f} {:>9.1f} {:>11} {:>12.0f} {:>8}\n", name,
                           r.fps_min, r.fps_max, r.fps_median, r.cache_misses, r.triangles_mean,
                           r.frames_epsilon_raised);
    }
    return out;
}

std::string formatRenderBenchJson(const RenderBenchReport& r)
{
    nlohmann::json frames = nlohmann::json::array();
    for (const FrameRecord& f : r.frames)
        frames.push_back({{"frame_ms", f.frame_ms},
                          {"select_ms", f.select_ms},
                          {"load_ms", f.load_ms},
                          {"gpu_ms", f.gpu_ms},
                          {"triangles", f.triangles},
                          {"patches", f.patches},
                          {"missing", f.missing},
                          {"loaded", f.loaded},
                          {"reconstructed", f.reconstructed},
                          {"epsilon_px", f.epsilon_px},
                          {"cache_hits", f.cache_hits},
                          {"cache_misses", f.cache_misses},
                          {"bytes_read", f.bytes_read},
                          {"bytes_decoded", f.bytes_decoded},
                          {"bytes_uploaded", f.bytes_uploaded},
                          {"rss_mib", f.rss_mib},
                          {"ram_cache_mib", f.ram_cache_mib},
                          {"hole_pixels", f.hole_pixels},
                          {"footprint_pixels", f.footprint_pixels},
                          {"popping_px", f.popping_px}});
    const nlohmann::json j = {{"archive", r.archive},
                              {"gl_renderer", r.gl_renderer},
                              {"renderer", r.options.scheme},
                              {"path", r.options.path.kind},
                              {"speed_mps", r.options.path.speed_mps},
                              {"size", {r.options.viewport.width, r.options.viewport.height}},
                              {"epsilon_px", r.options.epsilon_px},
                              {"texel_px", r.options.texel_px},
                              {"cull", r.options.cull},
                              {"chunks", r.options.grid_chunks ? "grid" : "simplified"},
                              {"chunk_tolerance", r.options.renderer.chunk_tolerance},
                              {"streaming", r.options.renderer.streaming},
                              {"hole_pixels", r.hole_pixels},
                              {"frames_with_holes", r.frames_with_holes},
                              {"popping_p99_px", r.popping_p99_px},
                              {"popping_max_px", r.popping_max_px},
                              {"gpu_reconstruction", r.options.renderer.gpu_reconstruction},
                              {"ram_mb", r.options.renderer.ram_budget_mb},
                              {"vram_mb", r.options.renderer.vram_budget_mb},
                              {"upload_mb", r.options.renderer.upload_budget_mb},
                              {"upload_ms", r.options.renderer.upload_budget_ms},
                              {"summary",
                               {{"fps_min", r.fps_min},
                                {"fps_median", r.fps_median},
                                {"fps_max", r.fps_max},
                                {"frame_ms_p99", r.frame_ms_p99},
                                {"frame_ms_max", r.frame_ms_max},
                                {"frames_over_twice_median", r.frames_over_twice_median},
                                {"bytes_read", r.bytes_read},
                                {"bytes_decoded", r.bytes_decoded},
                                {"bytes_uploaded", r.bytes_uploaded},
                                {"reconstructed", r.reconstructed},
                                {"rss_early_mib", r.rss_early_mib},
                                {"rss_end_mib", r.rss_end_mib},
                                {"mtri_per_s", r.mtri_per_s},
                                {"frames_missing", r.frames_missing},
                                {"select_ms_max", r.select_ms_max},
                                {"ram_cache_bytes", r.ram_cache_bytes},
                                {"cache_misses", r.cache_misses},
                                {"triangles_mean", r.triangles_mean},
                                {"frames_epsilon_raised", r.frames_epsilon_raised}}},
                              {"frames", frames}};
    return jsonText(j, 1) + "\n";
}

void writeRenderBenchJson(const RenderBenchReport& r, const std::string& path)
{
    refuseOutputOverInput(path, {r.archive, r.options.path.kind}); // kind: maybe a pose file
    writeFileAtomically(path, formatRenderBenchJson(r));
}

} // namespace ridge::renderbench
