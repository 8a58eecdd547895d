// The renderer's entry points refuse NaN, infinite and out-of-range parameters with messages
// naming them — settings, options, headless renders, the fly camera — before any GL call; and
// the renderer's ground height is lod::CoarseTerrain's, which never reads outside the root.
#include "fixture_archives.h"

#include "ridge/core/error.h"
#include "ridge/gpu/context.h"
#include "ridge/gpu/render_target.h"
#include "ridge/lod/coarse_terrain.h"
#include "ridge/render/fly_camera.h"
#include "ridge/render/headless_render.h"
#include "ridge/render/terrain_renderer.h"

#include "error_expectations.h"

#include "ridge/core/terrain_palette.h"
#include "ridge/render/legend.h"

#include <gtest/gtest.h>

#include <cfloat>
#include <filesystem>
#include <functional>
#include <limits>

using namespace ridge;

namespace {

using ridge::test::errorOf;
using ridge::test::expectError;

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

} // namespace

TEST(RenderValidation, RenderSettingsRefuseNanEpsilonAndSunAndSayTheRange)
{
    EXPECT_NO_THROW(render::RenderSettings{}.validate());
    render::RenderSettings s;
    s.epsilon_px = kNan;
    expectError([&] { s.validate(); }, "epsilon_px is nan: must be a number in [0.05, 1000]");
    s.epsilon_px = 0.0;
    expectError([&] { s.validate(); }, "epsilon_px is 0");
    s = {};
    s.sun_direction = glm::dvec3(kNan, 0, 1);
    expectError([&] { s.validate(); }, "sun_direction is (nan, 0, 1)");
    s.sun_direction = glm::dvec3(0.0);
    expectError([&] { s.validate(); }, "sun_direction is (0, 0, 0)");
    s = {};
    s.clear_colour.g = float(kInf);
    expectError([&] { s.validate(); }, "clear_colour");
}

TEST(RenderValidation, TexelSizeMustBeFiniteAndInRange)
{
    render::RenderSettings s;
    s.texel_px = 0.0; // off
    EXPECT_NO_THROW(s.validate());
    s.texel_px = kNan;
    expectError([&] { s.validate(); }, "texel_px is nan: must be a number in [0, 1000]");
    s.texel_px = -0.5;
    expectError([&] { s.validate(); }, "texel_px is -0.5");
    s.texel_px = kInf;
    expectError([&] { s.validate(); }, "texel_px is inf");
}

TEST(RenderValidation, LegendsKeyEveryLevelAndFactorInThePaletteColours)
{
    EXPECT_TRUE(render::legendEntries(render::DebugMode::Shaded, 6, 8).empty());
    const auto levels = render::legendEntries(render::DebugMode::LodLevels, 9, 8);
    ASSERT_EQ(levels.size(), 10u);
    EXPECT_EQ(levels[9].label, "9");
    EXPECT_EQ(levels[9].colour.r, palette::levelColour(9).r);
    const auto factors = render::legendEntries(render::DebugMode::TessellationFactors, 6, 8);
    ASSERT_EQ(factors.size(), 4u); // 1, 2, 4, 8
    EXPECT_EQ(factors.back().label, "8");
    EXPECT_EQ(factors.back().colour.r, palette::heat(1.f).r);
    // Drawn into the lower-left corner: the swatch of level 0 is there, the top row untouched.
    const int w = 200, h = 60;
    std::vector<uint8_t> rgb(size_t(w) * h * 3, 77);
    render::drawLegend(rgb.data(), w, h, 3, levels);
    size_t level0 = 0, changed_top = 0;
    const palette::Rgb c0 = palette::levelColour(0);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const uint8_t* p = &rgb[(size_t(y) * w + x) * 3];
            level0 += y >= 10 && x < w / 3 && p[0] == uint8_t(std::lround(c0.r * 255.f)) &&
                      p[1] == uint8_t(std::lround(c0.g * 255.f)) &&
                      p[2] == uint8_t(std::lround(c0.b * 255.f));
            changed_top += y < 10 && p[0] != 77;
        }
    EXPECT_GE(level0, 100u) << "a 12 x 12 swatch of level 0";
    EXPECT_EQ(changed_top, 0u);
    // Too small for one entry: left alone; bad channel counts refused.
    std::vector<uint8_t> tiny(size_t(8) * 8 * 3, 5);
    render::drawLegend(tiny.data(), 8, 8, 3, levels);
    EXPECT_EQ(std::count(tiny.begin(), tiny.end(), uint8_t(5)), 8 * 8 * 3);
    expectError([&] { render::drawLegend(tiny.data(), 8, 8, 2, levels); }, "channels is 2");
}

TEST(RenderValidation, SunDirectionFromAzimuthAndAltitude)
{
    const glm::dvec3 d = render::sunDirection(315.0, 45.0);
    const glm::dvec3 expected = render::RenderSettings{}.sun_direction;
    EXPECT_NEAR(d.x, expected.x, 1e-8);
    EXPECT_NEAR(d.y, expected.y, 1e-8);
    EXPECT_NEAR(d.z, expected.z, 1e-8);
    expectError([] { render::sunDirection(kNan, 45.0); }, "sun azimuth (degrees) is nan");
    expectError([] { render::sunDirection(315.0, kNan); }, "sun altitude (degrees) is nan");
    expectError([] { render::sunDirection(315.0, 0.0); }, "(0, 90]");
    expectError([] { render::sunDirection(1e300, 45.0); }, "[-360, 360]");
}

TEST(RenderValidation, RendererOptionsRefuseBudgetsThatAreZeroNanOrBeyondTheMachine)
{
    EXPECT_NO_THROW(render::RendererOptions{}.validate());
    EXPECT_NO_THROW(render::RendererOptions::streamingDefaults().validate());
    const std::vector<std::pair<std::function<void(render::RendererOptions&)>, std::string>> bad = {
        {[](auto& o) { o.vram_budget_mb = 0.0; },
         "vram_budget_mb is 0: must be a number in (0, 1e+06]"},
        {[](auto& o) { o.vram_budget_mb = kNan; }, "vram_budget_mb is nan"},
        {[](auto& o) { o.ram_budget_mb = 1e300; }, "ram_budget_mb is 1e+300"},
        {[](auto& o) { o.upload_budget_mb = -1.0; }, "upload_budget_mb"},
        {[](auto& o) { o.upload_budget_ms = kInf; }, "upload_budget_ms is inf"},
        {[](auto& o) { o.upload_frame_fraction = 1.0; },
         "upload_frame_fraction is 1: must be a number in [0, 1)"},
        {[](auto& o) { o.upload_budget_max_ms = kNan; }, "upload_budget_max_ms is nan"},
        {[](auto& o) { o.schemes = {"no-such-scheme"}; }, "no-such-scheme: not a LOD scheme"},
        {[](auto& o) { o.max_resident_patches = 2; }, "max_resident_patches is 2"},
        {[](auto& o) { o.io_threads = 0; }, "io_threads"},
        {[](auto& o) { o.uploads_per_frame = 0; }, "uploads_per_frame"},
        {[](auto& o) { o.prefetch_frames = -1; }, "prefetch_frames"},
        {[](auto& o) { o.decoded_cache_patches = 0; }, "decoded_cache_patches"},
    };
    for (const auto& [spoil, phrase] : bad) {
        render::RendererOptions o;
        spoil(o);
        expectError([&] { o.validate(); }, phrase);
    }
}

TEST(RenderValidation, HeadlessOptionsRefuseNanAndInfiniteCamerasBeforeOpeningTheArchive)
{
    render::HeadlessRenderOptions o;
    EXPECT_NO_THROW(o.validate());
    o.camera = glm::dvec3(kNan, 0, 0);
    expectError([&] { o.validate(); }, "camera position is (nan, 0, 0)");
    o.camera = glm::dvec3(kInf, 1, 1);
    expectError([&] { o.validate(); }, "camera position is (inf, 1, 1)");
    o.camera = glm::dvec3(1, 2, 3);
    o.look_at = glm::dvec3(0, -kInf, 0);
    expectError([&] { o.validate(); }, "camera look-at point is (0, -inf, 0)");
    o = {};
    o.fov_y_degrees = kNan;
    expectError([&] { o.validate(); }, "fov_y_degrees is nan: must be a number in [1, 170]");
    o = {};
    o.samples = 0;
    expectError([&] { o.validate(); }, "samples is 0");
    o = {};
    o.viewport = {20000, 10};
    expectError([&] { o.validate(); }, "image width is 20000");
    o = {};
    o.settings.epsilon_px = kNan;
    // The archive does not exist: the options are refused first, so their error is what shows.
    expectError([&] { render::renderToPng("/nonexistent.ridge", o, "/nonexistent.png"); },
                "epsilon_px is nan");
}

TEST(RenderValidation, TheFlyCameraRefusesNanInsteadOfPoisoningItsPose)
{
    expectError([] { render::FlyCamera({kNan, 0, 0}, 0, 0, 10); }, "fly camera position");
    expectError([] { render::FlyCamera({0, 0, 0}, kNan, 0, 10); }, "fly camera yaw");
    expectError([] { render::FlyCamera({0, 0, 0}, 0, 0, kNan); }, "fly camera speed");
    render::FlyCamera cam({0, 0, 0}, 0, 0, 10);
    render::FlyInput in;
    in.mouse_dx = kNan;
    expectError([&] { cam.update(in, 0.1); }, "fly camera input");
    in = {};
    expectError([&] { cam.update(in, kInf); }, "fly camera input");
    expectError([&] { cam.setSpeedFactor(kNan); }, "speed factor");
    expectError([&] { cam.setSensitivity(0.0); }, "sensitivity");
    EXPECT_EQ(cam.position(), glm::dvec3(0.0)) << "nothing changed";
    // Huge but finite: the speed clamps, a huge dt moves to the edge of the camera range.
    cam.scaleSpeed(1e300);
    EXPECT_EQ(cam.speed(), render::FlyCamera::kMaxSpeed);
    in.forward = true;
    cam.update(in, DBL_MAX);
    EXPECT_EQ(cam.position().y, lod::kCameraCoordinateRange.hi - 1.0);
    EXPECT_EQ(cam.position().x, 0.0);
    EXPECT_NO_THROW(cam.camera({64, 64}, 60, 1, 1e6));
}

TEST(RenderValidation, GroundHeightIsTheCoarseTerrainsAndNeverReadsOutOfBounds)
{
    test::ScratchDir scratch;
    const archive::ArchiveReader reader(test::buildEverestArchive(scratch));
    auto context = gpu::HeadlessContext::create();
    const render::TerrainRenderer renderer(reader);
    // An independent CoarseTerrain from the decoded root patch gives the same heights.
    const int n = reader.geometry().patchSize();
    std::vector<uint16_t> root(size_t(n) * n);
    reader.decodePatch(PatchId{0, 0, 0}, root.data());
    const lod::CoarseTerrain coarse(renderer.quadtree().frame(),
                                    renderer.quadtree().box(PatchId{0, 0, 0}), root,
                                    reader.quantization());
    const lod::TerrainFrame& f = renderer.quadtree().frame();
    for (const auto& [x, y] : {std::pair{0.0, 0.0},
                               {0.5 * f.extentX(), 0.3 * f.extentY()},
                               {f.extentX(), f.extentY()},
                               {-1e300, 1e300},
                               {DBL_MAX, -DBL_MAX}}) {
        const double h = renderer.groundHeight(x, y);
        EXPECT_EQ(h, coarse.groundHeight(x, y)) << x << ", " << y;
        EXPECT_GE(h, renderer.quadtree().bounds(PatchId{0, 0, 0}).min_height - 1e-3);
        EXPECT_LE(h, renderer.quadtree().bounds(PatchId{0, 0, 0}).max_height + 1e-3);
    }
    expectError([&] { renderer.groundHeight(kNan, 0.0); }, "ground point (x, y) is (nan, 0)");
    expectError([&] { renderer.groundHeight(0.0, -kInf); }, "ground point (x, y) is (0, -inf)");
    double near_m = 0, far_m = 0;
    expectError([&] { renderer.clipPlanesFor({kNan, 0, 0}, near_m, far_m); }, "camera position");
    const lod::Camera c = renderer.defaultCamera({160, 90});
    const lod::Camera d = coarse.defaultCamera({160, 90});
    EXPECT_EQ(c.position(), d.position());
    EXPECT_EQ(c.nearPlane(), d.nearPlane());
}

TEST(RenderValidation, DrawAndCaptureRefuseNanSettingsAndTheConstructorBadOptions)
{
    test::ScratchDir scratch;
    const archive::ArchiveReader reader(test::buildEverestArchive(scratch));
    auto context = gpu::HeadlessContext::create();
    render::RendererOptions bad;
    bad.vram_budget_mb = kNan;
    expectError([&] { render::TerrainRenderer r(reader, bad); }, "vram_budget_mb is nan");
    render::TerrainRenderer renderer(reader);
    const lod::Camera cam = renderer.defaultCamera({64, 64});
    const gpu::RenderTarget target(64, 64, 1);
    target.bind();
    render::RenderSettings s;
    s.epsilon_px = kNan;
    expectError([&] { renderer.draw(cam, s); }, "epsilon_px is nan");
    expectError([&] { renderer.capture(cam, s); }, "epsilon_px is nan");
    EXPECT_NO_THROW(renderer.draw(cam, {}));
}
