// A continent-scale view shows its continents (issue 13): the coarse ETOPO5 fixture
// (tests/data/etopo5_540x270.tif, the whole globe) rendered headless at the default ε from
// above, its pixels classified into land and sea by colour, against the heights under them
// and against `ridge hillshade` of the same archive. Before colour came from the patches'
// height maps (and before the texture-detail criterion), the default view was one patch of
// 184 triangles coloured by its vertices: the continents were gone.
#include "read_rgb.h"
#include "test_support.h"

#include "ridge/archive/archive_reader.h"
#include "ridge/lod/archive_frame.h"
#include "ridge/lod/terrain_frame.h"
#include "ridge/pipeline/build.h"
#include "ridge/pipeline/hillshade.h"
#include "ridge/pipeline/level_decoder.h"
#include "ridge/render/headless_render.h"

#include <gdal_priv.h>
#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cstdio>

using namespace ridge;

namespace {

using test::readRgb;

// Water in the shared palette is blue over green and red at any light; no land colour is
// (greens, ochres, browns, greys and snow, even under fog's bluish haze).
bool looksLikeWater(const uint8_t* p)
{
    return p[2] > p[0] + 24 && p[2] > p[1] + 8;
}

struct Heights {
    int width = 0, height = 0;
    std::vector<float> metres;
    float at(int i, int j) const { return metres[size_t(j) * size_t(width) + size_t(i)]; }
    // Land and sea alike within `r` samples: away from the coastline.
    bool awayFromCoast(int i, int j, int r) const
    {
        const bool land = at(i, j) > 0.f;
        for (int dj = -r; dj <= r; ++dj)
            for (int di = -r; di <= r; ++di) {
                const int x = std::clamp(i + di, 0, width - 1),
                          y = std::clamp(j + dj, 0, height - 1);
                if ((at(x, y) > 0.f) != land)
                    return false;
            }
        return true;
    }
};

struct Agreement {
    size_t compared = 0, agree = 0;
    size_t water_over_land = 0; // water-coloured pixels over land away from the coast
    double percent() const { return compared ? 100.0 * double(agree) / double(compared) : 0.0; }
};

class LandSea : public ::testing::Test {
  protected:
    static void SetUpTestSuite()
    {
        scratch_ = new test::ScratchDir();
        archive_ = scratch_->path("etopo5.ridge");
        BuildOptions options; // the CLI's defaults: patches of 129, lossless
        options.progress = {};
        buildArchive(test::dataPath("etopo5_540x270.tif"), archive_, options);
        const archive::ArchiveReader reader(archive_);
        const int finest = reader.geometry().finestLevel();
        const CodeGrid grid = decodeLevel(reader, finest);
        heights_.width = grid.width;
        heights_.height = grid.height;
        heights_.metres = toMetres(grid, reader.quantization());
    }
    static void TearDownTestSuite()
    {
        delete scratch_;
        scratch_ = nullptr;
    }

    // Renders from above the centre, looking down; `settings` as given (the defaults unless
    // a test changes them). Compares the pixel under every finest sample away from the coast.
    // `coast` is how far (finest samples) from the coastline a sample must be to count.
    // On the ellipsoid (`surface`) the view is the default camera's, the whole Earth from
    // above the grid's centre; a sample counts when it faces the camera well inside the limb.
    static Agreement renderAgreement(const render::RenderSettings& settings, const char* name,
                                     render::HeadlessRenderResult* result_out = nullptr,
                                     int coast = 2,
                                     lod::FrameChoice surface = lod::FrameChoice::Plane)
    {
        const archive::ArchiveReader reader(archive_);
        const lod::TerrainFrame frame = lod::terrainFrameOf(reader, surface, archive_);
        render::HeadlessRenderOptions options;
        options.viewport = {640, 360};
        options.fov_y_degrees = 30.0;
        options.settings = settings;
        options.frame = surface;
        if (!frame.onEllipsoid()) {
            const double cx = 0.5 * frame.extentX(), cy = 0.5 * frame.extentY();
            // High enough for the whole map to fit the frame (half-width over tan of half the
            // horizontal field of view); a hair north of straight down keeps "up" defined.
            const double h = 0.56 * frame.extentX() /
                             std::tan(std::atan(std::tan(15.0 * M_PI / 180.0) * 640.0 / 360.0));
            options.camera = glm::dvec3(cx, cy, h);
            options.look_at = glm::dvec3(cx, cy + 1e-3 * h, 0.0);
        }
        const std::string png = scratch_->path(std::string(name) + ".png");
        const render::HeadlessRenderResult result = render::renderToPng(archive_, options, png);
        if (result_out)
            *result_out = result;
        int w = 0, hgt = 0;
        const std::vector<uint8_t> rgb = readRgb(png, w, hgt);
        EXPECT_EQ(w, 640);
        Agreement a;
        for (int j = 0; j < heights_.height; ++j)
            for (int i = 0; i < heights_.width; ++i) {
                if (!heights_.awayFromCoast(i, j, coast))
                    continue;
                const glm::dvec3 world = frame.worldOf(i, j, heights_.at(i, j));
                if (frame.onEllipsoid() &&
                    glm::dot(glm::normalize(result.camera.position() - world), frame.upAt(i, j)) <
                        0.3)
                    continue; // beyond the horizon, or too near the limb to classify
                glm::dvec2 pixel;
                if (!result.camera.project(world, pixel))
                    continue;
                const int px = int(pixel.x), py = int(pixel.y);
                if (px < 0 || py < 0 || px >= w || py >= hgt)
                    continue;
                const bool water = looksLikeWater(&rgb[(size_t(py) * size_t(w) + size_t(px)) * 3]);
                const bool land = heights_.at(i, j) > 0.f;
                ++a.compared;
                a.agree += water != land;
                a.water_over_land += water && land;
            }
        return a;
    }

    static test::ScratchDir* scratch_;
    static std::string archive_;
    static Heights heights_;
};

test::ScratchDir* LandSea::scratch_ = nullptr;
std::string LandSea::archive_;
Heights LandSea::heights_;

} // namespace

TEST_F(LandSea, HillshadeColoursWaterExactlyWhereTheHeightIsAtOrBelowSeaLevel)
{
    const std::string png = scratch_->path("hillshade.png");
    writeHillshade(archive_, png, {});
    int w = 0, h = 0;
    const std::vector<uint8_t> rgb = readRgb(png, w, h);
    ASSERT_EQ(w, heights_.width);
    ASSERT_EQ(h, heights_.height);
    size_t agree = 0, land = 0;
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            const bool water = looksLikeWater(&rgb[(size_t(j) * size_t(w) + size_t(i)) * 3]);
            agree += water == (heights_.at(i, j) <= 0.f);
            land += heights_.at(i, j) > 0.f;
        }
    EXPECT_EQ(agree, size_t(w) * size_t(h)) << "the hillshade's water is the palette's: h <= 0 m";
    EXPECT_GT(land, size_t(w) * size_t(h) / 5) << "ETOPO5 is about 29 % land";
    EXPECT_LT(land, size_t(w) * size_t(h) / 2);
}

TEST_F(LandSea, DefaultRenderShowsTheContinentsTheHillshadeShows)
{
    render::HeadlessRenderResult result;
    const Agreement a = renderAgreement({}, "default", &result);
    std::printf("default settings (eps %.2g px, texel %.2g px): %zu patches, %llu triangles; "
                "land/sea agreement %.2f %% of %zu samples away from coasts, %zu water pixels "
                "over land\n",
                result.stats.epsilon_px, result.stats.texel_px, size_t(result.stats.patches),
                static_cast<unsigned long long>(result.stats.triangles), a.percent(), a.compared,
                a.water_over_land);
    EXPECT_GT(a.compared, 50000u) << "the globe must fill the frame";
    EXPECT_GE(a.percent(), 95.0);
    EXPECT_EQ(a.water_over_land, 0u) << "no water where the height under it is > 0";
}

TEST_F(LandSea, TheGlobeShowsTheContinentsTheHillshadeShows)
{
    // The same archive on the WGS 84 ellipsoid (auto: its columns go round the Earth), seen
    // by the default camera: the whole Earth from above the grid's centre (the Pacific).
    render::HeadlessRenderResult result;
    const Agreement a = renderAgreement({}, "globe", &result, 2, lod::FrameChoice::Auto);
    std::printf("globe, default camera: %d patches, %llu triangles; land/sea agreement %.2f %% "
                "of %zu samples away from coasts, %zu water pixels over land\n",
                result.stats.patches, static_cast<unsigned long long>(result.stats.triangles),
                a.percent(), a.compared, a.water_over_land);
    EXPECT_GT(a.compared, 15000u) << "a hemisphere must fill the frame";
    EXPECT_GE(a.percent(), 95.0);
    EXPECT_EQ(a.water_over_land, 0u);
}

TEST_F(LandSea, GeometryAloneStillColoursByTheDrawnPatchesMaps)
{
    // Without the texture-detail criterion the view is the root patch alone: colour still
    // comes from its height map (every 8th sample here), so the coastline is there, if
    // coarser; and with a fine ε no skirt hanging through 0 m shows as water (the ε 0.25 dots
    // over Asia). A sample more than one root cell (8 samples) from the coast has only land
    // (or only sea) at the corners of whichever level's cell it lies in: no water over land.
    const int root_step = 8;
    render::RenderSettings coarse;
    coarse.texel_px = 0.0;
    render::HeadlessRenderResult result;
    const Agreement a = renderAgreement(coarse, "geometry_only", &result, root_step);
    std::printf("texel criterion off: %d patches, land/sea agreement %.2f %%, %zu water pixels "
                "over land\n",
                result.stats.patches, a.percent(), a.water_over_land);
    EXPECT_EQ(a.water_over_land, 0u);
    EXPECT_GE(a.percent(), 99.0);
    render::RenderSettings fine;
    fine.texel_px = 0.0;
    fine.epsilon_px = 0.25;
    const Agreement f = renderAgreement(fine, "eps_025", &result, root_step);
    std::printf("eps 0.25, texel off: %d patches, land/sea agreement %.2f %%, %zu water pixels "
                "over land\n",
                result.stats.patches, f.percent(), f.water_over_land);
    EXPECT_GE(f.percent(), 95.0);
    EXPECT_EQ(f.water_over_land, 0u);
}

// Texture detail decoupled from geometry (issue 28): the texel criterion makes finer patches
// resident for shading, not drawn. The default view then draws exactly what ε alone draws —
// the same patches, the same triangles — while its colours come from the finer levels under
// the fragments: the coastline agrees with the finest data, where the drawn patch's own maps
// miss it by a sample here and there.
TEST_F(LandSea, TextureDetailShadesFromFinerLevelsWithoutDrawingMore)
{
    render::RenderSettings geometry_only;
    geometry_only.texel_px = 0.0;
    render::HeadlessRenderResult off, on;
    // Samples one finest sample or more from the coast: where the levels' coastlines differ.
    const Agreement a = renderAgreement(geometry_only, "detail_off", &off, 1);
    const Agreement b = renderAgreement({}, "detail_on", &on, 1);
    std::printf("texel off: %d patches, %llu triangles, agreement %.2f %%; texel %.2g px: %d "
                "patches, %llu triangles, agreement %.2f %% (of %zu samples)\n",
                off.stats.patches, static_cast<unsigned long long>(off.stats.triangles),
                a.percent(), on.stats.texel_px, on.stats.patches,
                static_cast<unsigned long long>(on.stats.triangles), b.percent(), b.compared);
    EXPECT_EQ(on.stats.patches, off.stats.patches) << "texture detail draws no patch more";
    EXPECT_EQ(off.stats.detail, 0);
    EXPECT_GT(on.stats.detail, 0);
    EXPECT_EQ(on.stats.detail_resident, on.stats.detail) << "no streaming: all of it resident";
    EXPECT_EQ(on.stats.triangles, off.stats.triangles);
    ASSERT_EQ(a.compared, b.compared);
    EXPECT_GE(b.percent(), 99.9);
    // The drawn patch's own maps miss its level's coast by a sample here and there (97.9 %
    // agree when measured); the finer levels' miss at most a tenth as many.
    EXPECT_GT(a.compared - a.agree, 100u);
    EXPECT_LE(b.compared - b.agree, (a.compared - a.agree) / 10) << "the finer levels' coastline";
    EXPECT_EQ(b.water_over_land, 0u);
}
