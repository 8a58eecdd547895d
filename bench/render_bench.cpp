// Renderer benchmarks (Google Benchmark) on the Sierra Nevada mosaic: frames of the
// tessellation renderer at 1920x1080 and the CPU cost of coarse LOD selection.
//
//   ./build/bench/ridge_bench_render     # data: $RIDGE_DATA_DIR or ../shared/data
//
// Without a GPU (Mesa llvmpipe) frame times are only meaningful as ratios between the
// variants run here (ε, skirts, culling); on a GPU machine they are the GPU's.
#include "ridge/gpu/context.h"
#include "ridge/gpu/render_target.h"
#include "ridge/pipeline/build.h"
#include "ridge/render/terrain_renderer.h"

#include <benchmark/benchmark.h>
#include <epoxy/gl.h>

#include <cstdlib>
#include <filesystem>
#include <memory>

using namespace ridge;

namespace {

struct Scene {
    std::string error;
    std::unique_ptr<gpu::HeadlessContext> context;
    std::unique_ptr<archive::ArchiveReader> reader;
    std::unique_ptr<render::TerrainRenderer> renderer;
    std::unique_ptr<gpu::RenderTarget> target;
};

Scene& scene()
{
    static Scene s = [] {
        Scene out;
        const char* dir = std::getenv("RIDGE_DATA_DIR");
        const std::string input = std::string(dir ? dir : RIDGE_SHARED_DATA_DIR) +
                                  "/sierra_nevada_sfbay_10801x4801_int16.tif";
        if (!std::filesystem::exists(input)) {
            out.error = "data not found, skipped: " + input;
            return out;
        }
        const std::string archive =
            (std::filesystem::temp_directory_path() / "ridge_bench_sierra.ridge").string();
        if (!std::filesystem::exists(archive))
            buildArchive(input, archive, BuildOptions{});
        out.context = gpu::HeadlessContext::create();
        out.reader = std::make_unique<archive::ArchiveReader>(archive);
        render::RendererOptions options;
        options.synchronous_stats = true;
        options.max_resident_patches = 2048; // brute force needs every finest patch in view
        options.vram_budget_mb = 512.0;
        out.renderer = std::make_unique<render::TerrainRenderer>(*out.reader, options);
        out.target = std::make_unique<gpu::RenderTarget>(1920, 1080, 1);
        return out;
    }();
    return s;
}

// 0: the whole mosaic from the default oblique view; 1: low over the Sierra foothills towards
// the crest (Yosemite), the view the paper's fly-over figures resemble.
lod::Camera view(int which)
{
    const render::TerrainRenderer& r = *scene().renderer;
    const lod::Viewport vp{1920, 1080};
    if (which == 0)
        return r.defaultCamera(vp);
    const glm::dvec3 pos(285000, 170000, 5200), at(318000, 196000, 2500);
    double near_m, far_m;
    r.clipPlanesFor(pos, near_m, far_m);
    return lod::Camera(pos, at, 60.0, vp, near_m, far_m);
}

void BM_TessellationFrame(benchmark::State& state)
{
    Scene& s = scene();
    if (!s.error.empty()) {
        state.SkipWithError(s.error.c_str());
        return;
    }
    const lod::Camera camera = view(int(state.range(0)));
    render::RenderSettings settings;
    settings.epsilon_px = double(state.range(1));
    settings.skirts = state.range(2) != 0;
    settings.cull = state.range(3) != 0;
    settings.cull_blocks = state.range(4) != 0;
    settings.scheme = render::LodScheme(state.range(5));
    s.target->bind();
    render::FrameStats stats = s.renderer->draw(camera, settings); // loads patches
    glFinish();
    for (auto _ : state) {
        stats = s.renderer->draw(camera, settings);
        glFinish();
    }
    state.counters["patches"] = stats.patches;
    state.counters["triangles"] = double(stats.triangles);
    state.counters["select_ms"] = stats.cpu_select_ms;
    state.counters["gpu_ms"] = stats.gpu_ms;
    state.counters["Mtri/s"] = benchmark::Counter(double(stats.triangles) * 1e-6,
                                                  benchmark::Counter::kIsIterationInvariantRate);
}
// view, ε, skirts, cull (patches), blocks (cull tessellation blocks too), scheme (0 tess,
// 1 chunked LOD, 2 brute force)
BENCHMARK(BM_TessellationFrame)
    ->ArgNames({"view", "eps", "skirts", "cull", "blocks", "scheme"})
    ->Args({0, 2, 1, 1, 1, 0})
    ->Args({1, 2, 1, 1, 1, 0})
    ->Args({1, 1, 1, 1, 1, 0})
    ->Args({1, 4, 1, 1, 1, 0})
    ->Args({1, 2, 0, 1, 1, 0})
    ->Args({1, 2, 1, 1, 0, 0})
    ->Args({1, 2, 1, 0, 0, 0})
    ->Args({1, 2, 1, 1, 1, 1})
    ->Args({1, 1, 1, 1, 1, 1})
    ->Args({1, 2, 1, 1, 1, 2})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

void BM_SelectPatches(benchmark::State& state)
{
    Scene& s = scene();
    if (!s.error.empty()) {
        state.SkipWithError(s.error.c_str());
        return;
    }
    const lod::Camera camera = view(int(state.range(0)));
    lod::SelectionSettings settings;
    settings.epsilon_px = double(state.range(1));
    settings.cull = state.range(2) != 0;
    size_t patches = 0;
    for (auto _ : state) {
        const lod::Selection selection = s.renderer->quadtree().select(camera, settings);
        patches = selection.patches.size();
        benchmark::DoNotOptimize(patches);
    }
    state.counters["patches"] = double(patches);
}
BENCHMARK(BM_SelectPatches)
    ->ArgNames({"view", "eps", "cull"})
    ->Args({0, 2, 1})
    ->Args({1, 2, 1})
    ->Args({1, 1, 1})
    ->Args({1, 2, 0})
    ->Unit(benchmark::kMicrosecond);

} // namespace

BENCHMARK_MAIN();
