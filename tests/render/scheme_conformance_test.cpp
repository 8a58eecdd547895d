// The conformance suite every registered LOD scheme runs (parameterised over the registry, on
// whatever GL the machine has — llvmpipe on CI). A new scheme gets every check here by
// registering, each against what it promises (render::SchemePromises, in its registration):
//   * the captured surface is watertight: with skirts, every interior edge of a patch shared
//     by two triangles with bit-identical endpoints and every seam between patches covered by
//     a skirt; with stitching, every edge of the whole surface shared by exactly two
//     triangles across pieces (degenerate triangles, which the rasteriser drops, left out);
//     open edges only on the terrain's border and at skirts' and walls' feet;
//   * every finest sample in view has surface above it, and its projected vertical error is
//     within ε where the scheme promises it — measured and reported (max, p99 in ε) for all;
//   * looking down, no background pixel inside the terrain's footprint;
//   * a streaming fly-over under a tiny texture budget never shows a hole;
//   * LOD changes along a camera path pop no more than a pop-free scheme promises — measured
//     and reported (max, p99 pixels) for all.
// Cameras of every kind the independent checker used: low (15–200 m above ground), along the
// steepest slopes, across the east and south borders, high, and far enough to draw only the
// coarsest levels; patches of 33, 65 and 129 samples; a low-relief terrain.
#include "captured_surface_checks.h"
#include "fixture_archives.h"

#include "ridge/codec/height_codec.h"
#include "ridge/gpu/context.h"
#include "ridge/gpu/render_target.h"
#include "ridge/pipeline/build.h"
#include "ridge/pipeline/level_decoder.h"
#include "ridge/render/frame_measures.h"
#include "ridge/render/terrain_renderer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <optional>
#include <random>

namespace ridge {
namespace {

// ε met within float rounding of camera-relative positions (~1e-3 px at these distances).
constexpr double kPromiseSlack = 1.001;
constexpr double kPromiseSlackPx = 1e-3;

struct Fixture {
    std::string name;
    std::string codec;
    int patch_size;
    double max_error; // lossy codecs: the codec's bound, metres
    double z_scale;   // 1: Everest as it is; 0.02: a low-relief terrain (60 m of relief)
};

// What the suite draws on, built once per process.
const std::vector<Fixture>& fixtures()
{
    static const std::vector<Fixture> all = {
        {"everest lossless 33", "lossless", 33, 0.0, 1.0},
        {"everest progressive 65", "progressive", 65, 1.0, 1.0},
        {"low relief lossless 129", "lossless", 129, 0.0, 0.02},
        // The JPEG2000 paper's model: lossy, decoded on the CPU, edges coded to agree.
        {"everest jpeg2000 33", "jpeg2000", 33, 1.0, 1.0},
    };
    return all;
}

struct Scene {
    std::unique_ptr<archive::ArchiveReader> reader;
    std::unique_ptr<render::TerrainRenderer> renderer;
    std::vector<float> finest; // the finest level as decoded, metres
};

class SchemeConformance : public ::testing::TestWithParam<std::string> {
  protected:
    static void SetUpTestSuite()
    {
        context_ = gpu::HeadlessContext::create().release();
        scratch_ = new test::ScratchDir();
    }
    static void TearDownTestSuite()
    {
        scenes_.clear();
        delete scratch_;
        delete context_;
    }

  public:
    static Scene& sceneOf(const Fixture& f) { return scene(f); }

  protected:
    // The synchronous renderer over fixture `f`, able to draw every registered scheme.
    static Scene& scene(const Fixture& f)
    {
        auto& s = scenes_[f.name];
        if (s.renderer)
            return s;
        BuildOptions options;
        options.patch_size = f.patch_size;
        options.codec = f.codec;
        if (isLossyCodec(f.codec))
            options.max_error = f.max_error;
        if (f.z_scale != 1.0)
            options.ingest.z_scale = f.z_scale;
        options.progress = {};
        const std::string path = scratch_->path(std::to_string(scenes_.size()) + ".ridge");
        buildArchive(test::dataPath("everest_crop.tif"), path, options);
        s.reader = std::make_unique<archive::ArchiveReader>(path);
        render::RendererOptions ro;
        ro.synchronous_stats = true;
        ro.max_resident_patches = 2048;
        ro.schemes = render::lodSchemeNames();
        s.renderer = std::make_unique<render::TerrainRenderer>(*s.reader, ro);
        const int finest = s.reader->geometry().finestLevel();
        const std::vector<uint16_t> codes = decodeLevel(*s.reader, finest).codes;
        s.finest.resize(codes.size());
        for (size_t i = 0; i < codes.size(); ++i)
            s.finest[i] = float(s.reader->quantization().toMetres(codes[i]));
        return s;
    }

    static test::ScratchDir* scratch_;
    static gpu::HeadlessContext* context_;
    static std::map<std::string, Scene> scenes_;
};

test::ScratchDir* SchemeConformance::scratch_ = nullptr;
gpu::HeadlessContext* SchemeConformance::context_ = nullptr;
std::map<std::string, Scene> SchemeConformance::scenes_;

struct NamedCamera {
    std::string kind;
    lod::Camera camera;
};

lod::Camera cameraAt(const render::TerrainRenderer& r, glm::dvec3 pos, glm::dvec3 at,
                     lod::Viewport vp)
{
    double near_m, far_m;
    r.clipPlanesFor(pos, near_m, far_m);
    return lod::Camera(pos, at, 60.0, vp, near_m, far_m);
}

// Every kind of camera the independent checker used, a few of each.
std::vector<NamedCamera> conformanceCameras(const Scene& s, lod::Viewport vp)
{
    const render::TerrainRenderer& r = *s.renderer;
    const lod::TerrainFrame& f = r.quadtree().frame();
    const lod::PatchBounds& root = r.quadtree().bounds({0, 0, 0});
    const double X = f.extentX(), Y = f.extentY(), relief = root.max_height - root.min_height;
    const int W = f.geometry().width(), H = f.geometry().height();
    std::vector<NamedCamera> out;
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    auto ground = [&](double x, double y) { return r.groundHeight(x, y); };
    // Low: 15–200 m above the ground, looking 1–3 km ahead and slightly down.
    for (int k = 0; k < 3; ++k) {
        const double x = X * (0.2 + 0.6 * u(rng)), y = Y * (0.2 + 0.6 * u(rng));
        const double above = 15.0 * std::pow(200.0 / 15.0, u(rng)), a = 6.283 * u(rng);
        const double d = 1000.0 + 2000.0 * u(rng);
        const glm::dvec3 pos(x, y, ground(x, y) + above + relief * 0.02);
        const double tx = x + d * std::cos(a), ty = y + d * std::sin(a);
        out.push_back({"low", cameraAt(r, pos, {tx, ty, ground(tx, ty)}, vp)});
    }
    // Along the steepest slope of the finest data, 100 m above it, looking downhill.
    {
        double best = -1.0;
        int bi = 1, bj = 1;
        for (int j = 1; j + 1 < H; ++j)
            for (int i = 1; i + 1 < W; ++i) {
                const double gx = s.finest[size_t(j) * W + i + 1] - s.finest[size_t(j) * W + i - 1];
                const double gy = s.finest[size_t(j + 1) * W + i] - s.finest[size_t(j - 1) * W + i];
                if (gx * gx + gy * gy > best) {
                    best = gx * gx + gy * gy;
                    bi = i;
                    bj = j;
                }
            }
        const double x = f.xOf(bi), y = f.yOf(bj);
        const double gx = s.finest[size_t(bj) * W + bi + 1] - s.finest[size_t(bj) * W + bi - 1];
        // Rows grow south: +row is −y.
        const double gy = -(s.finest[size_t(bj + 1) * W + bi] - s.finest[size_t(bj - 1) * W + bi]);
        const double len = std::max(std::hypot(gx, gy), 1e-9);
        const glm::dvec3 pos(x, y, s.finest[size_t(bj) * W + bi] + 100.0);
        for (double sign : {-1.0, 1.0}) { // downhill, then uphill
            const double tx = x + sign * 1500.0 * gx / len, ty = y + sign * 1500.0 * gy / len;
            out.push_back({"slope", cameraAt(r, pos, {tx, ty, ground(tx, ty)}, vp)});
        }
    }
    // Across the east and south borders: from outside, low and oblique, at the last column
    // and row (where coarse levels must still reach).
    const double mid = 0.5 * (root.min_height + root.max_height);
    out.push_back({"east border", cameraAt(r, {X + 2000.0, Y * 0.5, root.max_height + 500.0},
                                           {X, Y * 0.5, mid}, vp)});
    out.push_back({"south border", cameraAt(r, {X * 0.5, -2000.0, root.max_height + 500.0},
                                            {X * 0.5, 0.0, mid}, vp)});
    // High, oblique over the whole terrain, and far: only the coarsest levels are drawn.
    out.push_back({"high", cameraAt(r, {X * 0.4, -Y * 0.3, root.max_height + 2.0 * std::max(X, Y)},
                                    {X * 0.5, Y * 0.5, mid}, vp)});
    out.push_back(
        {"far",
         cameraAt(r, {X * 0.9 + 8.0 * X, Y * 0.1 - 8.0 * Y, root.max_height + 3.0 * std::max(X, Y)},
                  {X * 0.9, Y * 0.1, mid}, vp)});
    return out;
}

// `texel_px`: the texture-detail criterion, which only refines further. The captured-surface
// test measures what ε promises, so it turns it off (with the default 1 px it took 1.8× as long
// on llvmpipe, geomorph 3.3×: too slow for the sanitizer build's limits); the pixel tests keep
// the default, so the default configuration is checked for holes too.
render::RenderSettings settingsFor(const std::string& scheme, double epsilon,
                                   double texel_px = render::RenderSettings{}.texel_px)
{
    render::RenderSettings s;
    s.scheme = scheme;
    s.epsilon_px = epsilon;
    s.texel_px = texel_px;
    return s;
}

TEST_P(SchemeConformance, CapturedSurfaceIsWatertightCoveredAndWithinItsPromise)
{
    const std::string scheme = GetParam();
    const render::SchemePromises promises = render::lodSchemePromises(scheme);
    const lod::Viewport vp{320, 180};
    for (const Fixture& fx : fixtures()) {
        Scene& s = scene(fx);
        const lod::TerrainFrame& frame = s.renderer->quadtree().frame();
        double worst = 0.0, worst_p99 = 0.0; // ε-relative
        std::string worst_at;
        size_t degenerate = 0, triangles = 0;
        for (const double epsilon : {1.0, 4.0})
            for (const NamedCamera& nc : conformanceCameras(s, vp)) {
                const std::string where =
                    fx.name + ", " + nc.kind + " camera, ε " + std::to_string(int(epsilon));
                render::RenderSettings settings = settingsFor(scheme, epsilon, 0.0);
                const test::SeamReport w =
                    test::checkSeamsAsPromised(*s.renderer, nc.camera, settings, frame);
                EXPECT_EQ(w.problems, 0u) << where << ": " << w.first_problem;
                degenerate += w.degenerate;
                triangles += w.triangles;
                const render::CapturedSurface surface = s.renderer->capture(nc.camera, settings);
                const test::ScreenErrorReport e =
                    test::measureScreenSpaceError(surface, frame, s.finest, nc.camera);
                EXPECT_EQ(e.uncovered, 0u) << where << ": finest samples in view without surface";
                EXPECT_EQ(e.overlapped, 0u) << where << ": finest samples under two triangles";
                EXPECT_GT(e.samples, 0u) << where;
                if (promises.screen_space_error) {
                    EXPECT_LE(e.max_px, epsilon * kPromiseSlack + kPromiseSlackPx)
                        << where << ": " << e.max_px / epsilon << " ε";
                }
                worst_p99 = std::max(worst_p99, e.p99_px / epsilon);
                if (e.max_px / epsilon > worst) {
                    worst = e.max_px / epsilon;
                    worst_at = where;
                }
            }
        std::printf("[%s] %s: screen-space error at most %.3f ε, p99 %.3f ε (%s; %s)\n",
                    scheme.c_str(), fx.name.c_str(), worst, worst_p99, worst_at.c_str(),
                    promises.screen_space_error ? "promised ≤ ε" : "measured only");
        if (promises.seams == render::SchemePromises::Seams::Stitching)
            std::printf("[%s] %s: stitched, %zu of %zu captured triangles degenerate\n",
                        scheme.c_str(), fx.name.c_str(), degenerate, triangles);
    }
}

// LOD changes alone: along a short fly-over, each frame's camera drawn with the previous
// frame's LOD state and with its own (everything resident: the synchronous renderer), the
// displacement of every finest sample in view (render::measurePopping; `ridge bench
// --popping`'s GPU measure must agree with it on every frame). A pop-free scheme must stay below a
// hundredth of a pixel plus float rounding; the others are measured.
TEST_P(SchemeConformance, LodChangesPopOnlyWhereTheSchemeDoesNotPromiseOtherwise)
{
    const std::string scheme = GetParam();
    const render::SchemePromises promises = render::lodSchemePromises(scheme);
    const lod::Viewport vp{240, 160};
    for (const int fixture : {0, 2}) {
        const Fixture& fx = fixtures()[size_t(fixture)];
        Scene& s = scene(fx);
        const lod::TerrainFrame& f = s.renderer->quadtree().frame();
        const lod::PatchBounds& root = s.renderer->quadtree().bounds({0, 0, 0});
        std::vector<double> popping;
        std::optional<lod::Camera> previous;
        s.renderer->resetPopping();
        const int frames = 10;
        for (int k = 0; k < frames; ++k) {
            const double t = double(k) / (frames - 1);
            const glm::dvec3 at(f.extentX() * (0.3 + 0.4 * t), f.extentY() * 0.5, root.min_height);
            const glm::dvec3 pos =
                at + glm::dvec3(-0.15 * f.extentX(), -0.1 * f.extentY(),
                                root.max_height - root.min_height + 0.05 * f.extentX());
            const lod::Camera cam = cameraAt(*s.renderer, pos, at, vp);
            // Whole patches: block culling follows the camera that looks, not the LOD state.
            render::RenderSettings settings = settingsFor(scheme, 2.0, 0.0);
            settings.cull_blocks = false;
            std::optional<render::PoppingReport> cpu;
            if (previous) {
                const render::SampleHeights before = render::surfaceHeightsAtSamples(
                    s.renderer->capture(cam, settings, &*previous, true), f);
                const render::SampleHeights after =
                    render::surfaceHeightsAtSamples(s.renderer->capture(cam, settings), f);
                cpu = render::measurePopping(before, after, f, cam);
                popping.push_back(cpu->max_px);
            } else {
                s.renderer->capture(cam, settings); // the first LOD state
            }
            // The measure `ridge bench --popping` takes: one capture a frame, the previous
            // frame's surface standing for this camera with the previous LOD state.
            const render::PoppingReport gpu = s.renderer->measureFramePopping(cam, settings);
            if (cpu) {
                EXPECT_NEAR(gpu.max_px, cpu->max_px, 0.01 + 1e-3 * cpu->max_px) << "frame " << k;
                EXPECT_NEAR(double(gpu.samples), double(cpu->samples), 0.005 * double(cpu->samples))
                    << "frame " << k;
            } else {
                EXPECT_EQ(gpu.samples, 0u) << "the first frame has nothing to compare with";
            }
            previous = cam;
        }
        std::sort(popping.begin(), popping.end());
        const double max = popping.back(), median = popping[popping.size() / 2];
        std::printf("[%s] %s: popping per frame median %.4f px, max %.4f px (%s)\n", scheme.c_str(),
                    fx.name.c_str(), median, max,
                    promises.pop_free ? "promised pop-free" : "measured only");
        if (promises.pop_free) {
            EXPECT_LE(max, 0.01 + kPromiseSlackPx) << fx.name;
        }
    }
}

TEST_P(SchemeConformance, LookingDownNoBackgroundShowsInsideTheFootprint)
{
    const std::string scheme = GetParam();
    const lod::Viewport vp{320, 240};
    gpu::RenderTarget target(vp.width, vp.height, 1);
    for (const Fixture& fx : fixtures()) {
        Scene& s = scene(fx);
        const lod::TerrainFrame& f = s.renderer->quadtree().frame();
        const lod::PatchBounds& root = s.renderer->quadtree().bounds({0, 0, 0});
        std::mt19937 rng(3);
        std::uniform_real_distribution<double> u(0.0, 1.0);
        size_t footprint = 0;
        for (int k = 0; k < 4; ++k) {
            const glm::dvec3 at(f.extentX() * (0.2 + 0.6 * u(rng)),
                                f.extentY() * (0.2 + 0.6 * u(rng)), root.min_height);
            const double height = (0.2 + u(rng)) * std::max(f.extentX(), f.extentY());
            const glm::dvec3 pos =
                at + glm::dvec3(0.3 * height * (u(rng) - 0.5), 0.3 * height * (u(rng) - 0.5),
                                height + root.max_height);
            const lod::Camera cam = cameraAt(*s.renderer, pos, at, vp);
            target.bind();
            s.renderer->draw(cam, settingsFor(scheme, 2.0));
            const std::vector<float> depth = target.readDepth();
            std::vector<uint8_t> background(depth.size());
            for (size_t i = 0; i < depth.size(); ++i)
                background[i] = depth[i] == 0.f; // reverse-Z clears to 0
            const render::HoleReport h =
                render::countHolePixels(background, cam, f, root.min_height, root.max_height);
            footprint += h.footprint_pixels;
            EXPECT_EQ(h.hole_pixels, 0u) << fx.name << " camera " << k << ": first at ("
                                         << h.first_x << ", " << h.first_y << ")";
        }
        EXPECT_GT(footprint, 50000u) << fx.name << ": the cameras must look at the terrain";
    }
}

void streamingFlyOver(const std::string& scheme, const Fixture& fx);

TEST_P(SchemeConformance, StreamingFlyOverUnderATinyBudgetNeverShowsAHole)
{
    const std::string scheme = GetParam();
    // Progressive (GPU reconstruction where the scheme allows) and jpeg2000 (slow decodes).
    for (const int fixture : {1, 3})
        streamingFlyOver(scheme, fixtures()[fixture]);
}

void streamingFlyOver(const std::string& scheme, const Fixture& fx)
{
    SCOPED_TRACE(fx.name);
    Scene& synchronous = SchemeConformance::sceneOf(fx);
    render::RendererOptions options = render::RendererOptions::streamingDefaults();
    options.schemes = {scheme};
    options.max_resident_patches = 12; // a handful of slots: ε rises, ancestors stand in
    options.ram_budget_mb = 1.0;
    options.uploads_per_frame = 2;
    render::TerrainRenderer renderer(*synchronous.reader, options);
    const lod::TerrainFrame& f = renderer.quadtree().frame();
    const lod::PatchBounds& root = renderer.quadtree().bounds({0, 0, 0});
    const lod::Viewport vp{240, 160};
    gpu::RenderTarget target(vp.width, vp.height, 1);
    target.bind();
    const int frames = 24;
    size_t footprint = 0, holes = 0;
    for (int k = 0; k < frames; ++k) {
        const double t = double(k) / (frames - 1);
        const glm::dvec3 at(f.extentX() * (0.2 + 0.6 * t), f.extentY() * 0.5, root.min_height);
        const glm::dvec3 pos = at + glm::dvec3(-0.1 * f.extentX(), -0.2 * f.extentY(),
                                               root.max_height + 0.5 * f.extentX());
        const lod::Camera cam = cameraAt(renderer, pos, at, vp);
        renderer.draw(cam, settingsFor(scheme, 1.0));
        const std::vector<float> depth = target.readDepth();
        std::vector<uint8_t> background(depth.size());
        for (size_t i = 0; i < depth.size(); ++i)
            background[i] = depth[i] == 0.f;
        const render::HoleReport h =
            render::countHolePixels(background, cam, f, root.min_height, root.max_height);
        footprint += h.footprint_pixels;
        holes += h.hole_pixels;
        EXPECT_EQ(h.hole_pixels, 0u) << "frame " << k;
    }
    EXPECT_EQ(renderer.streamingError(), "");
    EXPECT_GT(footprint, size_t(frames) * 1000);
    std::printf("[%s] %s streaming fly-over, 12 slots: %zu hole pixels in %zu footprint pixels\n",
                scheme.c_str(), fx.name.c_str(), holes, footprint);
}

// A low fly-over, 20 m above the finest ground, streaming under the same tiny budget: the
// camera is inside the terrain's slab, so its rays are judged from itself where it is above
// the surface drawn under it (countHolePixels' surface_under_camera, from the frame's own
// triangles). Frames where an ancestor standing in rises above the camera are not judged.
TEST_P(SchemeConformance, ALowStreamingFlyOverNeverShowsAHole)
{
    const std::string scheme = GetParam();
    const Fixture& fx = fixtures()[1];
    Scene& synchronous = SchemeConformance::sceneOf(fx);
    render::RendererOptions options = render::RendererOptions::streamingDefaults();
    options.schemes = {scheme};
    options.max_resident_patches = 12;
    options.ram_budget_mb = 1.0;
    options.uploads_per_frame = 2;
    render::TerrainRenderer renderer(*synchronous.reader, options);
    const lod::TerrainFrame& f = renderer.quadtree().frame();
    const lod::PatchBounds& root = renderer.quadtree().bounds({0, 0, 0});
    const int W = synchronous.reader->geometry().width();
    const int H = synchronous.reader->geometry().height();
    // The highest finest sample around (x, y): the camera clears the ground it stands over.
    auto ground = [&](double x, double y) {
        const int c = std::clamp(int(x / f.spacingX()), 0, W - 2);
        const int r = std::clamp(int(y / f.spacingY()), 0, H - 2);
        float z = -1e30f;
        for (int dr = 0; dr <= 1; ++dr)
            for (int dc = 0; dc <= 1; ++dc)
                z = std::max(z, synchronous.finest[size_t(r + dr) * W + size_t(c + dc)]);
        return double(z);
    };
    const lod::Viewport vp{240, 160};
    gpu::RenderTarget target(vp.width, vp.height, 1);
    const int frames = 16;
    size_t footprint = 0, holes = 0;
    int judged = 0;
    for (int k = 0; k < frames; ++k) {
        const double t = double(k) / (frames - 1);
        const double x = f.extentX() * (0.15 + 0.5 * t), y = f.extentY() * 0.45;
        const glm::dvec3 pos(x, y, ground(x, y) + 20.0);
        const double ahead = x + 0.25 * f.extentX();
        const glm::dvec3 at(ahead, y + 0.1 * f.extentY(), ground(ahead, y));
        const lod::Camera cam = cameraAt(renderer, pos, at, vp);
        target.bind();
        renderer.draw(cam, settingsFor(scheme, 1.0));
        const std::vector<float> depth = target.readDepth();
        std::vector<uint8_t> background(depth.size());
        for (size_t i = 0; i < depth.size(); ++i)
            background[i] = depth[i] == 0.f;
        ASSERT_LT(pos.z, root.max_height) << "the camera must be inside the slab";
        const double under = render::surfaceHeightUnder(renderer.lastFrameSurface(), f, x, y);
        const render::HoleReport h = render::countHolePixels(background, cam, f, root.min_height,
                                                             root.max_height, 4.0, under);
        judged += h.footprint_pixels > 0;
        footprint += h.footprint_pixels;
        holes += h.hole_pixels;
        EXPECT_EQ(h.hole_pixels, 0u)
            << "frame " << k << ": first at (" << h.first_x << ", " << h.first_y << ")";
    }
    EXPECT_EQ(renderer.streamingError(), "");
    EXPECT_GE(judged, frames / 2) << "most frames must be judged";
    EXPECT_GT(footprint, size_t(judged) * 1000);
    std::printf("[%s] %s low streaming fly-over (20 m), 12 slots: %d of %d frames judged, %zu "
                "hole pixels in %zu footprint pixels\n",
                scheme.c_str(), fx.name.c_str(), judged, frames, holes, footprint);
}

// Streamed arrivals fade in (lod/arrival_blend.h): a camera holds still over the Everest
// fixture while its patches stream in a few a frame, progressive (parents before children:
// arrivals cascade), and each frame's surface is compared with the one before
// (measureFramePopping). Only arrivals change the surface, so with fades every frame moves by
// about the fade's step; without them (max_frames 0) arrivals jump by pixels, which shows
// the check can fail.
TEST_P(SchemeConformance, StreamedArrivalsFadeInInsteadOfPopping)
{
    const std::string scheme = GetParam();
    const Fixture& fx = fixtures()[1];
    Scene& synchronous = SchemeConformance::sceneOf(fx);
    const lod::Viewport vp{240, 160};
    auto run = [&](int max_frames, int& fading_frames) {
        render::RendererOptions options = render::RendererOptions::streamingDefaults();
        options.schemes = {scheme};
        options.uploads_per_frame = 2;
        options.prefetch_frames = 0;
        options.arrival_blend.max_frames = max_frames;
        options.arrival_blend.px_per_frame = 0.25;
        render::TerrainRenderer renderer(*synchronous.reader, options);
        const lod::TerrainFrame& f = renderer.quadtree().frame();
        const lod::PatchBounds& root = renderer.quadtree().bounds({0, 0, 0});
        const glm::dvec3 at(f.extentX() * 0.55, f.extentY() * 0.5, root.min_height);
        const glm::dvec3 pos = at + glm::dvec3(-0.2 * f.extentX(), -0.25 * f.extentY(),
                                               root.max_height - root.min_height);
        const lod::Camera cam = cameraAt(renderer, pos, at, vp);
        gpu::RenderTarget target(vp.width, vp.height, 1);
        render::RenderSettings settings = settingsFor(scheme, 1.0, 0.0);
        double worst = 0.0;
        fading_frames = 0;
        for (int k = 0; k < 24; ++k) { // everything has arrived by frame 12
            target.bind();
            const render::FrameStats stats = renderer.draw(cam, settings);
            fading_frames += stats.fading > 0;
            const render::PoppingReport pop = renderer.measureFramePopping(cam, settings);
            if (k > 0)
                worst = std::max(worst, pop.max_px);
        }
        EXPECT_EQ(renderer.streamingError(), "");
        return worst;
    };
    using Arrivals = render::SchemePromises::Arrivals;
    const Arrivals promise = render::lodSchemePromises(scheme).arrivals;
    int fading_off = 0, fading_on = 0;
    const double on = run(1000, fading_on);
    if (promise == Arrivals::Replace) {
        EXPECT_EQ(fading_on, 0) << "a scheme that replaces arrivals is told of no fades";
        std::printf("[%s] %s arrivals, static camera: popping max %.3f px a frame (replaced)\n",
                    scheme.c_str(), fx.name.c_str(), on);
        return;
    }
    const double off = run(0, fading_off);
    std::printf("[%s] %s arrivals, static camera: popping max %.3f px a frame without fades, "
                "%.3f px with (%d frames fading)\n",
                scheme.c_str(), fx.name.c_str(), off, on, fading_on);
    EXPECT_EQ(fading_off, 0);
    EXPECT_GT(off, 1.0) << "arrivals must jump without fades (the check must be able to fail)";
    switch (promise) {
    case Arrivals::Fade:
        EXPECT_GT(fading_on, 0);
        EXPECT_LE(on, 0.5) << "each frame moves by about the fade's step, 0.25 px a link";
        break;
    case Arrivals::FadeFromGrid:
        EXPECT_GT(fading_on, 0);
        EXPECT_LT(on, off) << "fading from the ancestors' grids must still help";
        break;
    case Arrivals::Replace:
        break;
    }
}

INSTANTIATE_TEST_SUITE_P(EveryRegisteredScheme, SchemeConformance,
                         ::testing::ValuesIn(render::lodSchemeNames()),
                         [](const auto& info) { return info.param; });

} // namespace
} // namespace ridge
