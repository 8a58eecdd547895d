// Renderer benchmarks (Google Benchmark) on the Sierra Nevada mosaic: frames of the
// tessellation renderer at 1920x1080, frames of every registered scheme and variant of its
// options, and the CPU cost of coarse LOD selection.
//
//   ./build/bench/ridge_bench_render     # data: $RIDGE_DATA_DIR or ../shared/data
//
// Without a GPU (Mesa llvmpipe) frame times are only meaningful as ratios between the
// variants run here (ε, skirts, culling); on a GPU machine they are the GPU's.
#include "ridge/gpu/context.h"
#include "ridge/gpu/render_target.h"
#include "ridge/lod/chunk_mesh.h"
#include "ridge/pipeline/build.h"
#include "ridge/render/scheme_options.h"
#include "ridge/render/terrain_renderer.h"
#include "ridge/stream/patch_loader.h"

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
    std::unique_ptr<render::TerrainRenderer> renderer; // the default scheme
    std::unique_ptr<gpu::RenderTarget> target;
    // The renderer of one scheme spec (BM_SchemeFrame), rebuilt when another is asked for.
    std::string scheme_spec;
    std::unique_ptr<render::TerrainRenderer> scheme_renderer;
};

render::RendererOptions benchOptions()
{
    render::RendererOptions options;
    options.synchronous_stats = true;
    options.max_resident_patches = 2048; // brute force needs every finest patch in view
    options.vram_budget_mb = 512.0;
    return options;
}

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
        render::RendererOptions options = benchOptions();
        options.schemes = {render::defaultLodScheme()};
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

// One frame of `renderer` drawing `settings` from `camera`, timed until the GPU finished it.
void timeFrames(benchmark::State& state, render::TerrainRenderer& renderer,
                const lod::Camera& camera, const render::RenderSettings& settings)
{
    Scene& s = scene();
    s.target->bind();
    render::FrameStats stats = renderer.draw(camera, settings); // loads patches
    glFinish();
    for (auto _ : state) {
        stats = renderer.draw(camera, settings);
        glFinish();
    }
    state.counters["patches"] = stats.patches;
    state.counters["triangles"] = double(stats.triangles);
    state.counters["select_ms"] = stats.cpu_select_ms;
    state.counters["gpu_ms"] = stats.gpu_ms;
    state.counters["Mtri/s"] = benchmark::Counter(double(stats.triangles) * 1e-6,
                                                  benchmark::Counter::kIsIterationInvariantRate);
}

// The default scheme (render::defaultLodScheme(): the paper's tessellation) under ε, skirts
// and culling.
void BM_TessellationFrame(benchmark::State& state)
{
    Scene& s = scene();
    if (!s.error.empty()) {
        state.SkipWithError(s.error.c_str());
        return;
    }
    render::RenderSettings settings;
    settings.epsilon_px = double(state.range(1));
    settings.skirts = state.range(2) != 0;
    settings.cull = state.range(3) != 0;
    settings.cull_blocks = state.range(4) != 0;
    timeFrames(state, *s.renderer, view(int(state.range(0))), settings);
}
// view, ε, skirts, cull (patches), blocks (cull tessellation blocks too)
BENCHMARK(BM_TessellationFrame)
    ->ArgNames({"view", "eps", "skirts", "cull", "blocks"})
    ->Args({0, 2, 1, 1, 1})
    ->Args({1, 2, 1, 1, 1})
    ->Args({1, 1, 1, 1, 1})
    ->Args({1, 4, 1, 1, 1})
    ->Args({1, 2, 0, 1, 1})
    ->Args({1, 2, 1, 1, 0})
    ->Args({1, 2, 1, 0, 0})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// Every registered scheme, and each value of its choices and flags (render::lodSchemeVariants():
// e.g. chunked LOD with Ulrich's simplified chunks and with full grids), from view 1 at ε 2
// and 1 px; each spec in a renderer of its own.
void BM_SchemeFrame(benchmark::State& state, const std::string& spec)
{
    Scene& s = scene();
    if (!s.error.empty()) {
        state.SkipWithError(s.error.c_str());
        return;
    }
    if (s.scheme_spec != spec) {
        s.scheme_renderer.reset();
        render::RendererOptions options = benchOptions();
        options.schemes = {spec};
        s.scheme_renderer = std::make_unique<render::TerrainRenderer>(*s.reader, options);
        s.scheme_spec = spec;
    }
    render::RenderSettings settings;
    settings.scheme = s.scheme_renderer->schemes().front();
    settings.epsilon_px = double(state.range(0));
    timeFrames(state, *s.scheme_renderer, view(1), settings);
}
[[maybe_unused]] const bool kSchemeFramesRegistered = [] {
    for (const std::string& spec : render::lodSchemeVariants())
        benchmark::RegisterBenchmark(("BM_SchemeFrame/" + spec).c_str(), BM_SchemeFrame, spec)
            ->ArgNames({"eps"})
            ->Arg(2)
            ->Arg(1)
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime();
    return true;
}();

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

// What an upload of Ulrich's chunk costs on the CPU: building the mesh of one 129² Sierra
// patch at 0.5·Err(P), as a ratio to decoding that patch (the baseline, same process). Levels
// 4 and 7 (finest); the patch under view 1's look-at point.
void BM_BuildChunkMesh(benchmark::State& state)
{
    Scene& s = scene();
    if (!s.error.empty()) {
        state.SkipWithError(s.error.c_str());
        return;
    }
    const int level = int(state.range(0));
    const bool decode_only = state.range(1) != 0;
    const archive::ArchiveReader& reader = *s.reader;
    const PyramidGeometry& g = reader.geometry();
    const int n = g.patchSize();
    const int64_t span = int64_t(g.cells()) * g.step(level);
    const lod::TerrainFrame& frame = s.renderer->quadtree().frame();
    const PatchId p{level, int(std::llround(frame.columnOf(318000)) / span),
                    int(std::llround(frame.rowOf(196000)) / span)};
    std::vector<uint16_t> codes(size_t(n) * n);
    reader.decodePatch(p, codes.data());
    size_t triangles = 0;
    for (auto _ : state) {
        if (decode_only) {
            reader.decodePatch(p, codes.data());
            benchmark::DoNotOptimize(codes.data());
        } else {
            const lod::ChunkMesh mesh = lod::buildChunkMesh(
                codes.data(), reader.geometry().patchSize(),
                0.5 * reader.record(p).err / reader.quantization().scale,
                reader.geometry().coveredCellsX(p), reader.geometry().coveredCellsY(p));
            triangles = mesh.surface_indices / 3;
            benchmark::DoNotOptimize(triangles);
        }
    }
    if (!decode_only)
        state.counters["triangles"] = double(triangles);
}
BENCHMARK(BM_BuildChunkMesh)
    ->ArgNames({"level", "decode"})
    ->Args({4, 1})
    ->Args({4, 0})
    ->Args({7, 1})
    ->Args({7, 0})
    ->Unit(benchmark::kMicrosecond);

} // namespace

BENCHMARK_MAIN();
