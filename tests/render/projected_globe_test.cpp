// A projected raster on the globe (issue 26): the UTM 45N fixture (tests/data/everest_utm45.tif,
// 262 x 197 samples of 90 m) drawn on the WGS 84 ellipsoid by every registered scheme — every
// sample in view within ε where the scheme promises it, covered, seams as promised, no
// background inside its footprint from above — and in its place: the same mountain from the
// geographic tile it was warped from (everest_crop.tif, on the ellipsoid too) fills the same
// pixels at the same depths, while that tile moved 1 km east does not.
#include "captured_surface_checks.h"
#include "gdal_translate.h"
#include "test_support.h"

#include "ridge/gpu/context.h"
#include "ridge/gpu/render_target.h"
#include "ridge/lod/ellipsoid.h"
#include "ridge/pipeline/build.h"
#include "ridge/pipeline/level_decoder.h"
#include "ridge/render/frame_measures.h"
#include "ridge/render/terrain_renderer.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

namespace ridge {
namespace {

struct Globe {
    std::unique_ptr<archive::ArchiveReader> reader;
    std::unique_ptr<render::TerrainRenderer> renderer;
};

class ProjectedGlobe : public ::testing::TestWithParam<std::string> {
  protected:
    static void SetUpTestSuite()
    {
        context_ = gpu::HeadlessContext::create().release();
        scratch_ = new test::ScratchDir();
        utm_ = new Globe(onEllipsoid(test::dataPath("everest_utm45.tif"), "utm"));
        const archive::ArchiveReader& r = *utm_->reader;
        for (uint16_t c : decodeLevel(r, r.geometry().finestLevel()).codes)
            finest_.push_back(float(r.quantization().toMetres(c)));
    }
    static void TearDownTestSuite()
    {
        // GL objects go before the context.
        for (Globe* g : {polar_, geographic_, moved_})
            delete g;
        polar_ = geographic_ = moved_ = nullptr;
        delete utm_;
        delete scratch_;
        delete context_;
    }

    static Globe onEllipsoid(const std::string& tif, const std::string& name)
    {
        const std::string path = scratch_->path(name + ".ridge");
        BuildOptions options;
        options.patch_size = 33; // rings' static grids need 32 cells for the levels here
        options.progress = {};
        buildArchive(tif, path, options);
        Globe g;
        g.reader = std::make_unique<archive::ArchiveReader>(path);
        render::RendererOptions ro;
        ro.synchronous_stats = true;
        ro.max_resident_patches = 512;
        ro.schemes = render::lodSchemeNames();
        ro.frame = lod::FrameChoice::Ellipsoid;
        g.renderer = std::make_unique<render::TerrainRenderer>(*g.reader, ro);
        return g;
    }

    // A camera `back` metres south-west of sample (c, r) of the UTM grid and `up` metres
    // above the ellipsoid, looking at the ground there.
    static lod::Camera cameraAt(double c, double r, double back, double up, lod::Viewport vp)
    {
        const lod::TerrainFrame& f = utm_->renderer->quadtree().frame();
        const lod::EnuBasis b = f.basisAt(c, r);
        const glm::dvec3 ground = f.worldOf(c, r, 0.0);
        const glm::dvec3 at = f.worldOf(c, r, utm_->renderer->groundUnder(ground));
        const glm::dvec3 pos = f.worldOf(c, r, up) - back * glm::normalize(b.east + b.north);
        return utm_->renderer->cameraLookingAt(pos, at, 60.0, vp);
    }

    struct Named {
        const char* kind;
        double c, r, back, up;
    };
    // Straight down from 60 km, oblique across the massif from 9 km, low over the summit
    // ridge, and from a corner so that the grid's edges are in view.
    static constexpr Named kCameras[] = {
        {"overhead", 131.0, 98.0, 1.0, 6.0e4},
        {"oblique", 131.0, 98.0, 1.5e4, 9000.0},
        {"low", 150.0, 110.0, 1500.0, 8600.0},
        {"corner", 0.0, 196.0, 6000.0, 12000.0},
    };

    static gpu::HeadlessContext* context_;
    static test::ScratchDir* scratch_;
    static Globe* utm_;
    static std::vector<float> finest_;
    // Made by the tests that need them, the first time.
    static Globe* polar_;
    static Globe* geographic_;
    static Globe* moved_;
};

gpu::HeadlessContext* ProjectedGlobe::context_ = nullptr;
test::ScratchDir* ProjectedGlobe::scratch_ = nullptr;
Globe* ProjectedGlobe::utm_ = nullptr;
Globe* ProjectedGlobe::polar_ = nullptr;
Globe* ProjectedGlobe::geographic_ = nullptr;
Globe* ProjectedGlobe::moved_ = nullptr;
std::vector<float> ProjectedGlobe::finest_;

// Each camera's capture against the scheme's promises: seams, coverage, ε. Returns the worst
// error in ε.
double checkCaptures(render::TerrainRenderer& renderer, const std::vector<float>& finest,
                     const std::string& scheme,
                     const std::vector<std::pair<std::string, lod::Camera>>& cameras)
{
    const lod::TerrainFrame& frame = renderer.quadtree().frame();
    EXPECT_NE(frame.projectedGrid(), nullptr);
    const render::SchemePromises promises = render::lodSchemePromises(scheme);
    double worst = 0.0;
    for (const double epsilon : {1.0, 4.0})
        for (const auto& [kind, cam] : cameras) {
            const std::string where = kind + ", ε " + std::to_string(int(epsilon));
            render::RenderSettings settings;
            settings.scheme = scheme;
            settings.epsilon_px = epsilon;
            settings.texel_px = 0.0;
            const test::SeamReport seams =
                test::checkSeamsAsPromised(renderer, cam, settings, frame);
            EXPECT_EQ(seams.problems, 0u) << where << ": " << seams.first_problem;
            const test::ScreenErrorReport e =
                test::measureScreenSpaceError(renderer.capture(cam, settings), frame, finest, cam);
            EXPECT_EQ(e.uncovered, 0u) << where << ": samples in view under no triangle";
            EXPECT_GT(e.samples, 1000u) << where;
            if (promises.screen_space_error) {
                EXPECT_LE(e.max_px, epsilon * 1.001 + 1e-3)
                    << where << ": " << e.max_px / epsilon << " ε";
            }
            worst = std::max(worst, e.max_px / epsilon);
        }
    return worst;
}

TEST_P(ProjectedGlobe, CapturedSurfaceStaysWithinItsPromiseAndIsWatertight)
{
    const std::string scheme = GetParam();
    std::vector<std::pair<std::string, lod::Camera>> cameras;
    for (const Named& n : kCameras)
        cameras.emplace_back(n.kind, cameraAt(n.c, n.r, n.back, n.up, {320, 180}));
    const double worst = checkCaptures(*utm_->renderer, finest_, scheme, cameras);
    std::printf(
        "[%s] UTM on the ellipsoid: screen-space error at most %.3f ε (%s)\n", scheme.c_str(),
        worst, render::lodSchemePromises(scheme).screen_space_error ? "promised" : "measured only");
}

// The same samples relabelled in the Antarctic polar stereographic projection with the South
// Pole in the middle of the grid: longitude turns through a whole circle round one sample,
// where the lattice's surface (in ECEF) stays smooth.
TEST_P(ProjectedGlobe, APolarGridIsWatertightRoundThePole)
{
    if (!polar_) {
        const std::string tif = scratch_->path("polar.tif");
        test::gdalTranslate(test::dataPath("everest_utm45.tif"), tif,
                            {"-a_srs", "EPSG:3031", "-a_ullr", "-11790", "8865", "11790", "-8865"});
        polar_ = new Globe(onEllipsoid(tif, "polar"));
    }
    const Globe& polar = *polar_;
    static const std::vector<float> finest = [&polar] {
        std::vector<float> metres;
        const archive::ArchiveReader& r = *polar.reader;
        for (uint16_t c : decodeLevel(r, r.geometry().finestLevel()).codes)
            metres.push_back(float(r.quantization().toMetres(c)));
        return metres;
    }();
    render::TerrainRenderer& renderer = *polar.renderer;
    const lod::TerrainFrame& f = renderer.quadtree().frame();
    // The pole is sample (130.5, 98): its point is (0, 0, −b).
    ASSERT_LT(glm::length(f.worldOf(130.5, 98.0, 0.0) -
                          glm::dvec3(0.0, 0.0, -f.geodetic().ellipsoid.b())),
              0.01);
    const glm::dvec3 pole = f.worldOf(130.5, 98.0, 0.0);
    const glm::dvec3 down(0.0, 0.0, 1.0); // the South Pole's up is −z
    auto looking = [&](glm::dvec3 from) {
        return renderer.cameraLookingAt(from, pole + renderer.groundUnder(pole) * -down, 60.0,
                                        {320, 180});
    };
    const std::vector<std::pair<std::string, lod::Camera>> cameras = {
        {"over the pole", looking(pole - 3.0e4 * down + glm::dvec3(100.0, 0.0, 0.0))},
        {"low across the pole", looking(pole - 9000.0 * down + glm::dvec3(6000.0, 4000.0, 0.0))},
    };
    const double worst = checkCaptures(renderer, finest, GetParam(), cameras);
    std::printf("[%s] polar grid round the South Pole: screen-space error at most %.3f ε\n",
                GetParam().c_str(), worst);
}

TEST_P(ProjectedGlobe, NoBackgroundShowsInsideTheGridsFootprint)
{
    render::TerrainRenderer& renderer = *utm_->renderer;
    const lod::Viewport vp{320, 240};
    gpu::RenderTarget target(vp.width, vp.height, 1);
    const lod::PatchBounds& root = renderer.quadtree().bounds({0, 0, 0});
    render::RenderSettings settings;
    settings.scheme = GetParam();
    // From above: the judged rays start outside the sphere round all the terrain and cross
    // the grid both at its top (a + max) and below its bottom (b + min), 14 km above and 13 km
    // below the ground at 28°N, so the footprint is the middle of the raster.
    for (const Named& n : {Named{"overhead", 131.0, 98.0, 1.0, 6.0e4},
                           Named{"tilted", 100.0, 120.0, 1.0e4, 8.0e4}}) {
        const lod::Camera cam = cameraAt(n.c, n.r, n.back, n.up, vp);
        target.bind();
        renderer.draw(cam, settings);
        const std::vector<float> depth = target.readDepth();
        std::vector<uint8_t> background(depth.size());
        for (size_t i = 0; i < depth.size(); ++i)
            background[i] = depth[i] == 0.f;
        const render::HoleReport h = render::countHolePixels(
            background, cam, renderer.quadtree().frame(), root.min_height, root.max_height);
        EXPECT_GT(h.footprint_pixels, 1000u) << n.kind;
        EXPECT_EQ(h.hole_pixels, 0u)
            << n.kind << ": first at (" << h.first_x << ", " << h.first_y << ")";
    }
}

// The median relative difference of the depths two renderers draw from `cam`, over the pixels
// both cover.
double medianDepthDifference(render::TerrainRenderer& a, render::TerrainRenderer& b,
                             const lod::Camera& cam, const std::string& scheme, size_t& common)
{
    const lod::Viewport vp = cam.viewport();
    gpu::RenderTarget target(vp.width, vp.height, 1);
    render::RenderSettings settings;
    settings.scheme = scheme;
    std::vector<float> depth[2];
    for (int k = 0; k < 2; ++k) {
        target.bind();
        (k == 0 ? a : b).draw(cam, settings);
        depth[k] = target.readDepth();
    }
    std::vector<double> ratio;
    for (size_t i = 0; i < depth[0].size(); ++i)
        if (depth[0][i] > 0.f && depth[1][i] > 0.f)
            ratio.push_back(std::abs(double(depth[0][i]) / double(depth[1][i]) - 1.0));
    common = ratio.size();
    if (ratio.empty())
        return INFINITY;
    std::nth_element(ratio.begin(), ratio.begin() + ratio.size() / 2, ratio.end());
    return ratio[ratio.size() / 2];
}

TEST_P(ProjectedGlobe, SitsWhereTheGeographicTileItCameFromDoes)
{
    if (!geographic_) {
        geographic_ = new Globe(onEllipsoid(test::dataPath("everest_crop.tif"), "geographic"));
        // everest_crop.tif 0.01° (~980 m) east of where it belongs.
        const std::string tif = scratch_->path("moved.tif");
        test::gdalTranslate(test::dataPath("everest_crop.tif"), tif,
                            {"-a_ullr", "86.759583333333", "28.000416666667", "87.010416666667",
                             "27.831250000000"});
        moved_ = new Globe(onEllipsoid(tif, "moved"));
    }
    const Globe& geographic = *geographic_;
    const Globe& moved = *moved_;
    const lod::Camera cam = cameraAt(131.0, 98.0, 1.5e4, 9000.0, {320, 240});
    size_t common = 0, common_moved = 0;
    const double same =
        medianDepthDifference(*utm_->renderer, *geographic.renderer, cam, GetParam(), common);
    const double off =
        medianDepthDifference(*utm_->renderer, *moved.renderer, cam, GetParam(), common_moved);
    std::printf("[%s] UTM against its geographic source: median depth difference %.4f%% over "
                "%zu pixels; against the source moved 1 km east: %.4f%%\n",
                GetParam().c_str(), 100.0 * same, common, 100.0 * off);
    EXPECT_GT(common, 20000u);
    EXPECT_LT(same, 0.005);
    EXPECT_GT(off, 3.0 * same);
}

INSTANTIATE_TEST_SUITE_P(Schemes, ProjectedGlobe, ::testing::ValuesIn(render::lodSchemeNames()),
                         [](const auto& info) { return info.param; });

} // namespace
} // namespace ridge
