// The conformance suite on the globe (issue 26): every registered scheme that promises a
// wrapping globe draws the whole-Earth fixture (tests/data/etopo5_globe_256x129.tif: 1.40625°
// samples, 256 columns a turn, wrapping, both poles; 256 columns so that rings' tiles divide
// the turn) on the WGS 84 ellipsoid: every sample in view within ε where the scheme promises
// it (the straight cells' sag below the curved surface counted) and covered by the captured
// surface; seams watertight as the scheme promises them, across the wrap seam and at both
// poles; no background inside the globe's footprint from orbit, over the wrap seam (the
// prime meridian here) and over both poles; and no hole while streaming under a tiny budget
// on the way down. A scheme that does not promise it refuses by name.
#include "captured_surface_checks.h"
#include "test_support.h"

#include "ridge/core/error.h"
#include "ridge/gpu/context.h"
#include "ridge/gpu/render_target.h"
#include "ridge/lod/ellipsoid.h"
#include "ridge/pipeline/build.h"
#include "ridge/pipeline/level_decoder.h"
#include "ridge/render/frame_measures.h"
#include "ridge/render/terrain_renderer.h"

#include <glm/exponential.hpp>
#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <memory>
#include <numbers>
#include <optional>

namespace ridge {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

class GlobeConformance : public ::testing::TestWithParam<std::string> {
  protected:
    static void SetUpTestSuite()
    {
        context_ = gpu::HeadlessContext::create().release();
        scratch_ = new test::ScratchDir();
        archive_ = scratch_->path("globe.ridge");
        BuildOptions options;
        options.patch_size = 17;
        options.progress = {};
        buildArchive(test::dataPath("etopo5_globe_256x129.tif"), archive_, options);
        reader_ = new archive::ArchiveReader(archive_);
        render::RendererOptions ro;
        ro.synchronous_stats = true;
        ro.max_resident_patches = 1024;
        ro.schemes = render::lodSchemeNames();
        renderer_ = new render::TerrainRenderer(*reader_, ro); // auto: the ellipsoid
        const std::vector<uint16_t> codes =
            decodeLevel(*reader_, reader_->geometry().finestLevel()).codes;
        for (uint16_t c : codes)
            finest_.push_back(float(reader_->quantization().toMetres(c)));
    }
    static void TearDownTestSuite()
    {
        delete renderer_;
        delete reader_;
        delete scratch_;
        delete context_;
    }

    // A camera at (lon, lat, height) looking at (lon, lat) on the ground.
    static lod::Camera camera(const render::TerrainRenderer& r, double lon, double lat, double h,
                              double at_lon, double at_lat, lod::Viewport vp)
    {
        const lod::Ellipsoid e = r.quadtree().frame().geodetic().ellipsoid;
        const glm::dvec3 pos = lod::geodeticToEcef(e, lon * kDeg, lat * kDeg, h);
        const glm::dvec3 ground = lod::geodeticToEcef(e, at_lon * kDeg, at_lat * kDeg, 0.0);
        const glm::dvec3 at =
            lod::geodeticToEcef(e, at_lon * kDeg, at_lat * kDeg, r.groundUnder(ground));
        return r.cameraLookingAt(pos, at, 60.0, vp);
    }

    struct Named {
        const char* kind;
        double lon, lat, h, at_lon, at_lat;
    };
    // From orbit, over the wrap seam (0° = 360°), over each pole, low over the Himalaya and
    // low across the seam.
    static constexpr Named kCameras[] = {
        {"orbit", 150.0, 10.0, 2.0e7, 150.0, 10.0},
        {"seam", 0.0, 20.0, 3.0e6, 0.0, 0.0},
        {"north pole", 30.0, 70.0, 3.0e6, 30.0, 90.0},
        {"south pole", -60.0, -72.0, 2.0e6, -60.0, -90.0},
        {"himalaya", 86.0, 24.0, 1.5e5, 87.0, 30.0},
        {"seam low", -6.0, 40.0, 2.0e5, 4.0, 42.0},
    };

    static gpu::HeadlessContext* context_;
    static test::ScratchDir* scratch_;
    static std::string archive_;
    static archive::ArchiveReader* reader_;
    static render::TerrainRenderer* renderer_;
    static std::vector<float> finest_;
};

gpu::HeadlessContext* GlobeConformance::context_ = nullptr;
test::ScratchDir* GlobeConformance::scratch_ = nullptr;
std::string GlobeConformance::archive_;
archive::ArchiveReader* GlobeConformance::reader_ = nullptr;
render::TerrainRenderer* GlobeConformance::renderer_ = nullptr;
std::vector<float> GlobeConformance::finest_;

render::RenderSettings settingsFor(const std::string& scheme, double epsilon, double texel_px)
{
    render::RenderSettings s;
    s.scheme = scheme;
    s.epsilon_px = epsilon;
    s.texel_px = texel_px;
    return s;
}

// A scheme that does not promise a wrapping globe (render::SchemePromises::wrapping_globe)
// must refuse it by name, not draw it wrong: that is what is checked for it.
bool refusesTheGlobe(render::TerrainRenderer& r, const std::string& scheme)
{
    if (render::lodSchemePromises(scheme).wrapping_globe)
        return false;
    render::RenderSettings s;
    s.scheme = scheme;
    const lod::Camera cam = r.defaultCamera({64, 64});
    try {
        r.capture(cam, s);
        ADD_FAILURE() << scheme << " drew a wrapping globe it does not promise";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find(scheme), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("--frame plane"), std::string::npos) << e.what();
    }
    return true;
}

// What ε promises, and the seams: every captured edge shared as the scheme promises (the
// pole's fan and the skirts meeting on the polar axis, and the edge meridian's cut, are
// judged as such: captured_surface_checks.cpp), every sample in view under a triangle.
TEST_P(GlobeConformance, CapturedSurfaceStaysWithinItsPromiseAndIsWatertight)
{
    const std::string scheme = GetParam();
    if (refusesTheGlobe(*renderer_, scheme))
        return;
    const render::SchemePromises promises = render::lodSchemePromises(scheme);
    const lod::TerrainFrame& frame = renderer_->quadtree().frame();
    ASSERT_TRUE(frame.onEllipsoid());
    const lod::Viewport vp{320, 180};
    double worst = 0.0;
    size_t problems = 0, uncovered = 0, samples = 0;
    for (const double epsilon : {1.0, 4.0})
        for (const Named& n : kCameras) {
            const std::string where = std::string(n.kind) + ", ε " + std::to_string(int(epsilon));
            const lod::Camera cam = camera(*renderer_, n.lon, n.lat, n.h, n.at_lon, n.at_lat, vp);
            const render::RenderSettings settings = settingsFor(scheme, epsilon, 0.0);
            const test::SeamReport seams =
                test::checkSeamsAsPromised(*renderer_, cam, settings, frame);
            problems += seams.problems;
            EXPECT_EQ(seams.problems, 0u) << where << ": " << seams.first_problem;
            const test::ScreenErrorReport e = test::measureScreenSpaceError(
                renderer_->capture(cam, settings), frame, finest_, cam);
            uncovered += e.uncovered;
            EXPECT_EQ(e.uncovered, 0u) << where << ": samples in view under no triangle";
            EXPECT_EQ(e.overlapped, 0u) << where << ": samples under two triangles";
            samples += e.samples;
            EXPECT_GT(e.samples, 0u) << where;
            if (promises.screen_space_error) {
                EXPECT_LE(e.max_px, epsilon * 1.001 + 1e-3)
                    << where << ": " << e.max_px / epsilon << " ε";
            }
            worst = std::max(worst, e.max_px / epsilon);
        }
    std::printf("[%s] globe: screen-space error at most %.3f ε (%s) over %zu samples; seam "
                "problems %zu, samples uncovered %zu\n",
                scheme.c_str(), worst,
                promises.screen_space_error ? "promised ≤ ε" : "measured only", samples, problems,
                uncovered);
}

// The globe's haze is the air's: thin from orbit looking down, thick where a low view looks
// far across the ground (a uniform fog tuned to the Earth's size, as on the plane, leaves
// both alike, next to nothing). Measured as how far fog moves each terrain pixel's colour
// towards the fog's, in [0, 1].
TEST(GlobeFog, ThinsWithAltitudeAndThickensWithTheAirCrossed)
{
    const auto context = gpu::HeadlessContext::create();
    test::ScratchDir dir;
    const std::string path = dir.path("globe.ridge");
    BuildOptions build;
    build.patch_size = 17;
    build.progress = {};
    buildArchive(test::dataPath("etopo5_globe_181x91.tif"), path, build);
    const archive::ArchiveReader reader(path);
    render::TerrainRenderer renderer(reader, render::RendererOptions{});
    ASSERT_TRUE(renderer.quadtree().frame().onEllipsoid());
    const lod::Viewport vp{160, 120};
    gpu::RenderTarget target(vp.width, vp.height, 1);
    const lod::Ellipsoid e = renderer.quadtree().frame().geodetic().ellipsoid;
    auto cameraAt = [&](double lon, double lat, double h, double at_lon, double at_lat) {
        const glm::dvec3 ground = lod::geodeticToEcef(e, at_lon * kDeg, at_lat * kDeg, 0.0);
        const glm::dvec3 at =
            lod::geodeticToEcef(e, at_lon * kDeg, at_lat * kDeg, renderer.groundUnder(ground));
        return renderer.cameraLookingAt(lod::geodeticToEcef(e, lon * kDeg, lat * kDeg, h), at, 60.0,
                                        vp);
    };
    // Per terrain pixel row (0 at the top): the mean fog share of its terrain pixels.
    auto fogByRow = [&](const lod::Camera& cam) {
        std::vector<std::vector<uint8_t>> rgba;
        std::vector<float> depth;
        for (const bool fog : {false, true}) {
            render::RenderSettings s;
            s.fog = fog;
            target.bind();
            renderer.draw(cam, s);
            rgba.push_back(target.readRgba());
            depth = target.readDepth();
        }
        const glm::dvec3 haze = glm::dvec3(0.78, 0.84, 0.90) * 255.0; // render::kHorizonColour
        std::vector<double> share(size_t(vp.height), -1.0);
        for (int y = 0; y < vp.height; ++y) {
            double sum = 0.0;
            int count = 0;
            for (int x = 0; x < vp.width; ++x) {
                const size_t i = size_t(y) * vp.width + x;
                if (depth[i] == 0.f)
                    continue; // sky or space
                const glm::dvec3 off(rgba[0][4 * i], rgba[0][4 * i + 1], rgba[0][4 * i + 2]);
                const glm::dvec3 on(rgba[1][4 * i], rgba[1][4 * i + 1], rgba[1][4 * i + 2]);
                const double span =
                    glm::length(glm::pow(haze / 255.0, glm::dvec3(1 / 1.1)) * 255.0 - off);
                if (span < 20.0)
                    continue; // terrain already the fog's colour: nothing to measure
                sum += std::min(1.0, glm::length(on - off) / span);
                ++count;
            }
            if (count > vp.width / 4)
                share[size_t(y)] = sum / count;
        }
        return share;
    };
    // From 20,000 km straight down at the Pacific: a faint haze.
    const std::vector<double> orbit = fogByRow(cameraAt(-160.0, 0.0, 2.0e7, -160.0, 0.0));
    EXPECT_LT(orbit[size_t(vp.height / 2)], 0.15) << "looking straight down from orbit";
    // 3 km over the Pacific, looking 150 km north: the far ground under the horizon fades.
    const std::vector<double> low = fogByRow(cameraAt(-160.0, 0.0, 3000.0, -160.0, 1.35));
    double far = -1.0, near = -1.0;
    for (size_t y = 0; y < low.size(); ++y)
        if (low[y] >= 0.0) {
            if (far < 0.0)
                far = low[y]; // the first terrain row from the top: the farthest ground
            near = low[y];    // the last: the nearest
        }
    ASSERT_GE(far, 0.0) << "the low view shows ground";
    EXPECT_GT(far, 0.5) << "ground ~200 km away through sea-level air";
    EXPECT_LT(near, far);
    std::printf("globe fog share: orbit %.3f (centre), low view far %.3f, near %.3f\n",
                orbit[size_t(vp.height / 2)], far, near);
}

// LOD changes alone on the globe, as on the plane: along a descent towards the Himalaya,
// each frame's camera drawn with the previous frame's LOD state and with its own, the
// displacement of every finest sample in view (render::measurePopping on the ellipsoid).
// Pop-free schemes stay below a hundredth of a pixel plus float rounding; the others are
// measured.
TEST_P(GlobeConformance, LodChangesPopOnlyWhereTheSchemeDoesNotPromiseOtherwise)
{
    const std::string scheme = GetParam();
    if (refusesTheGlobe(*renderer_, scheme))
        return;
    const render::SchemePromises promises = render::lodSchemePromises(scheme);
    const lod::TerrainFrame& f = renderer_->quadtree().frame();
    const lod::Viewport vp{240, 160};
    std::vector<double> popping;
    size_t samples = 0;
    std::optional<lod::Camera> previous;
    const int frames = 10;
    for (int k = 0; k < frames; ++k) {
        const double t = double(k) / (frames - 1);
        const double h = 3.0e6 * std::pow(2.0e5 / 3.0e6, t); // 3,000 km down to 200 km
        const lod::Camera cam =
            camera(*renderer_, 80.0 + 4.0 * t, 20.0 + 5.0 * t, h, 87.0, 30.0, vp);
        const render::RenderSettings settings = settingsFor(scheme, 2.0, 0.0);
        if (previous) {
            const render::SampleHeights before = render::surfaceHeightsAtSamples(
                renderer_->capture(cam, settings, &*previous, true), f);
            const render::SampleHeights after =
                render::surfaceHeightsAtSamples(renderer_->capture(cam, settings), f);
            const render::PoppingReport p = render::measurePopping(before, after, f, cam);
            popping.push_back(p.max_px);
            samples += p.samples;
        } else {
            renderer_->capture(cam, settings); // the first LOD state
        }
        previous = cam;
    }
    EXPECT_GT(samples, 1000u) << "the descent must look at the ground";
    std::sort(popping.begin(), popping.end());
    const double max = popping.back(), median = popping[popping.size() / 2];
    std::printf("[%s] globe: popping per frame median %.4f px, max %.4f px over %zu samples (%s)\n",
                scheme.c_str(), median, max, samples,
                promises.pop_free ? "promised pop-free" : "measured only");
    if (promises.pop_free) {
        EXPECT_LE(max, 0.01 + 1e-3);
    }
}

// And no terrain pixel is black: shading that went NaN (normals at a pole) shows as such.
TEST_P(GlobeConformance, NoBackgroundShowsInsideTheGlobesFootprint)
{
    const std::string scheme = GetParam();
    if (refusesTheGlobe(*renderer_, scheme))
        return;
    const lod::Viewport vp{320, 240};
    gpu::RenderTarget target(vp.width, vp.height, 1);
    const lod::PatchBounds& root = renderer_->quadtree().bounds({0, 0, 0});
    size_t footprint = 0;
    for (const Named& n : kCameras) {
        const lod::Camera cam = camera(*renderer_, n.lon, n.lat, n.h, n.at_lon, n.at_lat, vp);
        target.bind();
        renderer_->draw(cam, settingsFor(scheme, 2.0, render::RenderSettings{}.texel_px));
        const std::vector<float> depth = target.readDepth();
        const std::vector<uint8_t> rgba = target.readRgba();
        std::vector<uint8_t> background(depth.size());
        size_t black = 0; // drawn but unshaded: a NaN normal (a pole's degenerate tangents)
        for (size_t i = 0; i < depth.size(); ++i) {
            background[i] = depth[i] == 0.f; // reverse-Z clears to 0
            black +=
                !background[i] && rgba[4 * i] == 0 && rgba[4 * i + 1] == 0 && rgba[4 * i + 2] == 0;
        }
        const render::HoleReport h = render::countHolePixels(
            background, cam, renderer_->quadtree().frame(), root.min_height, root.max_height);
        footprint += h.footprint_pixels;
        EXPECT_EQ(h.hole_pixels, 0u)
            << n.kind << ": first at (" << h.first_x << ", " << h.first_y << ")";
        EXPECT_EQ(black, 0u) << n.kind << ": terrain pixels shaded black";
    }
    EXPECT_GT(footprint, 100000u) << "the cameras must look at the globe";
}

TEST_P(GlobeConformance, StreamingFromOrbitDownUnderATinyBudgetShowsNoHole)
{
    const std::string scheme = GetParam();
    if (refusesTheGlobe(*renderer_, scheme))
        return;
    render::RendererOptions options = render::RendererOptions::streamingDefaults();
    options.schemes = {scheme};
    options.max_resident_patches = 12;
    options.ram_budget_mb = 1.0;
    options.uploads_per_frame = 2;
    render::TerrainRenderer renderer(*reader_, options);
    const lod::PatchBounds& root = renderer.quadtree().bounds({0, 0, 0});
    const lod::Viewport vp{240, 160};
    gpu::RenderTarget target(vp.width, vp.height, 1);
    target.bind();
    const int frames = 16;
    size_t footprint = 0, holes = 0;
    int frames_with_holes = 0;
    for (int k = 0; k < frames; ++k) {
        const double t = double(k) / (frames - 1);
        // From 20,000 km down to 300 km, drifting east across the seam.
        const double h = 2e7 * std::pow(300e3 / 2e7, t);
        const lod::Camera cam =
            camera(renderer, -20.0 + 40.0 * t, 30.0, h, -15.0 + 40.0 * t, 35.0, vp);
        const render::FrameStats stats =
            renderer.draw(cam, settingsFor(scheme, 1.0, render::RenderSettings{}.texel_px));
        const std::vector<float> depth = target.readDepth();
        std::vector<uint8_t> background(depth.size());
        for (size_t i = 0; i < depth.size(); ++i)
            background[i] = depth[i] == 0.f;
        // A dozen slots raise ε a long way: the limb may fall short by twice the ε met.
        const render::HoleReport hole =
            render::countHolePixels(background, cam, renderer.quadtree().frame(), root.min_height,
                                    root.max_height, std::max(4.0, 2.0 * stats.epsilon_px));
        footprint += hole.footprint_pixels;
        holes += hole.hole_pixels;
        frames_with_holes += hole.hole_pixels > 0;
        EXPECT_EQ(hole.hole_pixels, 0u)
            << "frame " << k << " at " << h / 1000 << " km: first at (" << hole.first_x << ", "
            << hole.first_y << "); ε met " << stats.epsilon_px << " px, " << stats.patches
            << " patches";
    }
    EXPECT_EQ(renderer.streamingError(), "");
    EXPECT_GT(footprint, size_t(frames) * 1000);
    std::printf("[%s] globe streaming, 12 slots: %zu hole pixels in %d of %d frames (%zu "
                "footprint pixels)\n",
                scheme.c_str(), holes, frames_with_holes, frames, footprint);
}

INSTANTIATE_TEST_SUITE_P(EveryRegisteredScheme, GlobeConformance,
                         ::testing::ValuesIn(render::lodSchemeNames()),
                         [](const auto& info) { return info.param; });

} // namespace
} // namespace ridge
