// Scheme "clipmaps"' own behaviour beyond the conformance suite: every level size watertight
// with its trims, fix-ups, transition regions and perimeters; a level shift writes only its
// strip (the first frame writes every window, a small move a sliver of that, standing still
// nothing); streaming never waits (the first frames draw the coarsest level, the finer ones
// follow as their patches arrive, never a hole); options the windows cannot take refused
// naming the file and the option; and on a wrapping globe, levels that fit it or a refusal.
#include "captured_surface_checks.h"
#include "error_expectations.h"
#include "terrain_renderer_fixture.h"

#include "ridge/core/error.h"
#include "ridge/gpu/render_target.h"
#include "ridge/lod/ellipsoid.h"
#include "ridge/pipeline/build.h"
#include "ridge/pipeline/level_decoder.h"
#include "ridge/render/frame_measures.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <numbers>

using namespace ridge;

namespace {

class ClipmapsScheme : public test::TerrainRendererTest {};

lod::Camera lowCamera(const render::TerrainRenderer& r, double x, double y)
{
    const glm::dvec3 pos(x, y, r.groundHeight(x, y) + 300.0);
    const glm::dvec3 at(x + 3000.0, y + 2000.0, r.groundHeight(x + 3000.0, y + 2000.0));
    return lod::Camera(pos, at, 60.0, {320, 200}, 1.0, 1e6);
}

} // namespace

TEST_F(ClipmapsScheme, EveryLevelSizeIsWatertightWithItsTrimsFixUpsAndPerimeters)
{
    for (const std::string spec :
         {"clipmaps,n=63", "clipmaps,n=127", "clipmaps", "clipmaps,n=511"}) {
        SCOPED_TRACE(spec);
        const test::Scene s = scene("lossless", 0.0, {spec});
        const lod::TerrainFrame& f = s.renderer->quadtree().frame();
        render::RenderSettings settings;
        settings.scheme = "clipmaps";
        settings.cull = false;
        for (const double at : {0.3, 0.55, 0.8}) {
            const lod::Camera camera = lowCamera(*s.renderer, at * f.extentX(), at * f.extentY());
            const render::CapturedSurface surface = s.renderer->capture(camera, settings);
            const test::StitchedReport w = test::checkStitchedWatertight(surface, f);
            EXPECT_GT(w.triangles, 1000u);
            EXPECT_EQ(w.open_edges, 0u) << w.first_problem;
            EXPECT_EQ(w.overused_edges, 0u);
        }
    }
}

TEST_F(ClipmapsScheme, ALevelShiftWritesOnlyItsStripAndStandingStillWritesNothing)
{
    const test::Scene s = scene("lossless", 0.0, {"clipmaps,n=63"});
    const lod::TerrainFrame& f = s.renderer->quadtree().frame();
    gpu::RenderTarget target(320, 200, 1);
    target.bind();
    render::RenderSettings settings;
    settings.scheme = "clipmaps";
    const double x = 0.5 * f.extentX(), y = 0.5 * f.extentY();
    const render::FrameStats first = s.renderer->draw(lowCamera(*s.renderer, x, y), settings);
    ASSERT_GT(first.levels, 1);
    // The first frame fills every window.
    EXPECT_EQ(first.level_shifts, first.levels);
    EXPECT_EQ(first.samples_written, uint64_t(63 * 63) * uint64_t(first.levels));
    EXPECT_EQ(first.levels_drawn, first.levels_wanted);
    // Two finest samples east: the finest level shifts by two columns (a 2 × 63 strip), the
    // coarser ones at most by one of their own columns each.
    const render::FrameStats moved =
        s.renderer->draw(lowCamera(*s.renderer, x + 2.0 * f.spacingX(), y), settings);
    EXPECT_GE(moved.level_shifts, 1);
    EXPECT_GE(moved.samples_written, uint64_t(2 * 63));
    EXPECT_LE(moved.samples_written, uint64_t(2 * 63) * uint64_t(moved.level_shifts));
    const render::FrameStats still =
        s.renderer->draw(lowCamera(*s.renderer, x + 2.0 * f.spacingX(), y), settings);
    EXPECT_EQ(still.level_shifts, 0);
    EXPECT_EQ(still.samples_written, 0u);
}

TEST_F(ClipmapsScheme, StreamingDrawsTheCoarsestLevelAtOnceAndTheFinerOnesAsTheyArrive)
{
    const test::Scene built = scene("lossless", 0.0, {"clipmaps"});
    render::RendererOptions options = render::RendererOptions::streamingDefaults();
    options.schemes = {"clipmaps"};
    options.uploads_per_frame = 1;
    render::TerrainRenderer renderer(*built.reader, options);
    const lod::TerrainFrame& f = renderer.quadtree().frame();
    const lod::PatchBounds& root = renderer.quadtree().bounds({0, 0, 0});
    gpu::RenderTarget target(320, 200, 1);
    target.bind();
    render::RenderSettings settings;
    settings.scheme = "clipmaps";
    const lod::Camera camera = lowCamera(renderer, 0.4 * f.extentX(), 0.4 * f.extentY());
    bool waited = false;
    int frames = 0;
    for (; frames < 200; ++frames) {
        const render::FrameStats stats = renderer.draw(camera, settings);
        EXPECT_GE(stats.levels_drawn, 1) << "the coarsest level reads the root: always drawn";
        const std::vector<float> depth = target.readDepth();
        std::vector<uint8_t> background(depth.size());
        for (size_t i = 0; i < depth.size(); ++i)
            background[i] = depth[i] == 0.f;
        EXPECT_EQ(render::countHolePixels(background, camera, f, root.min_height, root.max_height)
                      .hole_pixels,
                  0u)
            << "frame " << frames;
        waited = waited || stats.levels_drawn < stats.levels_wanted;
        if (stats.levels_drawn == stats.levels_wanted && waited)
            break;
        renderer.waitForStreaming(1.0);
    }
    EXPECT_TRUE(waited) << "one upload a frame: the finer levels wait for their patches";
    EXPECT_LT(frames, 200) << "every wanted level drawn once its patches arrived";
    EXPECT_EQ(renderer.streamingError(), "");
}

TEST_F(ClipmapsScheme, OptionsTheWindowsCannotTakeAreRefusedNamingTheArchiveAndTheOption)
{
    const std::string path = test::buildEverestArchive(*scratch_, "lossless", 33, 0.0);
    const archive::ArchiveReader reader(path);
    for (const auto& [spec, expected] :
         {std::pair<std::string, std::string>{"clipmaps,n=100", "n 100 must be 2^k − 1"},
          {"clipmaps,n=256", "n 256 must be 2^k − 1"},
          {"clipmaps,n=31", "n=31"},
          {"clipmaps,levels=25", "levels=25"}}) {
        SCOPED_TRACE(spec);
        render::RendererOptions o;
        o.schemes = {spec};
        const std::string m = test::errorOf([&] { render::TerrainRenderer r(reader, o); });
        EXPECT_NE(m.find(expected), std::string::npos) << m;
    }
    // A valid n names the archive when it is refused later: too little texture memory for
    // the windows and the slots.
    render::RendererOptions o;
    o.schemes = {"clipmaps,n=1023"};
    o.vram_budget_mb = 2.0;
    const std::string m = test::errorOf([&] { render::TerrainRenderer r(reader, o); });
    EXPECT_NE(m.find(path), std::string::npos) << m;
}

// On a globe whose columns go round the Earth the coarsest cells must divide the turn and the
// rows to a pole (lod::checkClipmapGlobe): the 2° whole-Earth fixture (180 columns a turn,
// 90 rows pole to pole) takes at most 2 levels. More are refused naming the archive, the
// option and the levels that fit; the default scheme set leaves clipmaps out; 2 levels of 127
// (the coarser a turn wide, cut to one) draw the globe across the antimeridian watertight,
// every sample in view under one triangle.
TEST_F(ClipmapsScheme, OnAGlobeTheLevelsMustFitTheTurnAndThePolesAndThenDrawIt)
{
    const std::string path = scratch_->path("globe.ridge");
    BuildOptions build;
    build.patch_size = 17;
    build.progress = {};
    buildArchive(test::dataPath("etopo5_globe_181x91.tif"), path, build);
    const archive::ArchiveReader reader(path);
    render::RendererOptions o;
    o.schemes = {"clipmaps,n=63,levels=3"};
    const std::string m = test::errorOf([&] { render::TerrainRenderer r(reader, o); });
    EXPECT_NE(m.find(path), std::string::npos) << m;
    EXPECT_NE(m.find("--lod clipmaps,n=63,levels=3"), std::string::npos) << m;
    EXPECT_NE(m.find("the 90 rows to its south pole"), std::string::npos) << m;
    EXPECT_NE(m.find("levels=2 or fewer"), std::string::npos) << m;
    {
        const render::TerrainRenderer defaults(reader, render::RendererOptions{});
        const std::vector<std::string>& names = defaults.schemes();
        EXPECT_EQ(std::count(names.begin(), names.end(), "clipmaps"), 0);
    }
    o.schemes = {"clipmaps,n=127,levels=2"}; // the coarser window 252 columns wide: cut to the turn
    o.synchronous_stats = true;
    render::TerrainRenderer r(reader, o);
    ASSERT_TRUE(r.quadtree().frame().onEllipsoid());
    render::RenderSettings s;
    s.scheme = "clipmaps";
    const lod::Ellipsoid e = r.quadtree().frame().geodetic().ellipsoid;
    constexpr double kDeg = std::numbers::pi / 180.0;
    // Over the antimeridian (column 90 of 180 from 0° east), 1,500 km up, looking north-east.
    const glm::dvec3 pos = lod::geodeticToEcef(e, 179.0 * kDeg, 10.0 * kDeg, 1.5e6);
    const glm::dvec3 at = lod::geodeticToEcef(e, -170.0 * kDeg, 25.0 * kDeg, 0.0);
    const lod::Camera cam = r.cameraLookingAt(pos, at, 60.0, {240, 160});
    const test::SeamReport seams = test::checkSeamsAsPromised(r, cam, s, r.quadtree().frame());
    EXPECT_EQ(seams.problems, 0u) << seams.first_problem;
    const std::vector<uint16_t> codes = decodeLevel(reader, reader.geometry().finestLevel()).codes;
    std::vector<float> finest;
    for (uint16_t c : codes)
        finest.push_back(float(reader.quantization().toMetres(c)));
    const test::ScreenErrorReport err =
        test::measureScreenSpaceError(r.capture(cam, s), r.quadtree().frame(), finest, cam);
    EXPECT_GT(err.samples, 100u);
    EXPECT_EQ(err.uncovered, 0u);
    EXPECT_EQ(err.overlapped, 0u);
}
