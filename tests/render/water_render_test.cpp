// Every LOD scheme draws water where the archive's sample flags say, not where the decoded
// height is at or below 0 m (issue 22): the coastal fixture (tests/data/sfbay_coast.tif, sea
// at exactly 0 m) built lossy within 1 m decodes much of its sea as up to +1 m, which the
// renderer used to paint as flat green land; and a lake 87 m above the sea, from a vector
// layer, is water although no height rule could say so.
#include "read_rgb.h"
#include "test_support.h"

#include "ridge/archive/archive_reader.h"
#include "ridge/io/raster_source.h"
#include "ridge/lod/terrain_frame.h"
#include "ridge/pipeline/build.h"
#include "ridge/render/headless_render.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

using namespace ridge;

namespace {

bool looksLikeWater(const uint8_t* p)
{
    return p[2] > p[0] + 24 && p[2] > p[1] + 8;
}

struct Counts {
    size_t sea = 0, sea_as_water = 0, land = 0, land_as_water = 0, lake = 0, lake_as_water = 0;
};

class WaterRender : public ::testing::Test {
  protected:
    static void SetUpTestSuite()
    {
        scratch_ = new test::ScratchDir();
        archive_ = scratch_->path("coast.ridge");
        BuildOptions options;
        options.codec = "progressive";
        options.max_error = 1.0;
        options.patch_size = 65;
        options.ingest.water_layer = test::dataPath("crystal_springs_utm10.geojson");
        buildArchive(test::dataPath("sfbay_coast.tif"), archive_, options);
        io::ReferenceRaster r(test::dataPath("sfbay_coast.tif"), io::IngestOptions{});
        width_ = r.width();
        height_ = r.height();
        source_.resize(size_t(width_) * height_);
        r.readRows(0, height_, source_.data());
    }
    static void TearDownTestSuite()
    {
        delete scratch_;
        scratch_ = nullptr;
    }

    static double at(int i, int j) { return source_[size_t(j) * width_ + i]; }
    // Sea (0 m), lake (87 m) or land alike within `r` samples, and `r` samples inside the
    // raster (a border sample's pixel may be the sky, which is blue too).
    static int kind(int i, int j) { return at(i, j) <= 0.0 ? 0 : at(i, j) == 87.0 ? 2 : 1; }
    static bool awayFromEdges(int i, int j, int r)
    {
        if (i < r || j < r || i >= width_ - r || j >= height_ - r)
            return false;
        for (int dj = -r; dj <= r; ++dj)
            for (int di = -r; di <= r; ++di) {
                const int x = std::clamp(i + di, 0, width_ - 1),
                          y = std::clamp(j + dj, 0, height_ - 1);
                if (kind(x, y) != kind(i, j))
                    return false;
            }
        return true;
    }

    // From above the centre, looking down, the whole fixture in frame.
    static Counts render(const std::string& scheme)
    {
        const archive::ArchiveReader reader(archive_);
        const lod::TerrainFrame frame(reader.geometry(), reader.header().spacing_x,
                                      reader.header().spacing_y);
        render::HeadlessRenderOptions options;
        options.viewport = {640, 640};
        options.fov_y_degrees = 30.0;
        options.settings.scheme = scheme;
        const double cx = 0.5 * frame.extentX(), cy = 0.5 * frame.extentY();
        const double h =
            0.6 * std::max(frame.extentX(), frame.extentY()) / std::tan(15.0 * M_PI / 180.0);
        options.camera = glm::dvec3(cx, cy, h);
        options.look_at = glm::dvec3(cx, cy + 1e-3 * h, 0.0);
        const std::string png = scratch_->path(scheme + ".png");
        const render::HeadlessRenderResult result = render::renderToPng(archive_, options, png);
        int w = 0, hgt = 0;
        const std::vector<uint8_t> rgb = test::readRgb(png, w, hgt);
        Counts c;
        for (int j = 0; j < height_; ++j)
            for (int i = 0; i < width_; ++i) {
                // A water colour covers the surface where the blend of its samples' flags is
                // >= 1/2: at most half a cell past the last water sample.
                if (!awayFromEdges(i, j, 1))
                    continue;
                glm::dvec2 pixel;
                if (!result.camera.project({frame.xOf(i), frame.yOf(j), at(i, j)}, pixel))
                    continue;
                const int px = int(pixel.x), py = int(pixel.y);
                if (px < 0 || py < 0 || px >= w || py >= hgt)
                    continue;
                const bool water = looksLikeWater(&rgb[(size_t(py) * size_t(w) + size_t(px)) * 3]);
                switch (kind(i, j)) {
                case 0:
                    ++c.sea;
                    c.sea_as_water += water;
                    break;
                case 1:
                    ++c.land;
                    c.land_as_water += water;
                    break;
                default:
                    ++c.lake;
                    c.lake_as_water += water;
                }
            }
        std::printf("%s: sea %zu/%zu water, lake %zu/%zu, land %zu/%zu water\n", scheme.c_str(),
                    c.sea_as_water, c.sea, c.lake_as_water, c.lake, c.land_as_water, c.land);
        return c;
    }

    static test::ScratchDir* scratch_;
    static std::string archive_;
    static int width_, height_;
    static std::vector<double> source_;
};

test::ScratchDir* WaterRender::scratch_ = nullptr;
std::string WaterRender::archive_;
int WaterRender::width_ = 0, WaterRender::height_ = 0;
std::vector<double> WaterRender::source_;

} // namespace

TEST_F(WaterRender, EverySchemePaintsTheSeaAndTheLakeOfALossyArchiveAsWater)
{
    for (const std::string& scheme : render::lodSchemeNames()) {
        const Counts c = render(scheme);
        EXPECT_GT(c.sea, 10000u) << scheme << ": the sea must be in the frame";
        EXPECT_GT(c.lake, 20u) << scheme << ": ... and the lake";
        EXPECT_EQ(c.sea_as_water, c.sea) << scheme;
        EXPECT_EQ(c.lake_as_water, c.lake) << scheme;
        EXPECT_EQ(c.land_as_water, 0u) << scheme;
    }
}
