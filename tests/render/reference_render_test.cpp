// A fixed view of the bundled Everest fixture against a stored reference picture
// (tests/data/render_reference_everest.png). Regenerate it deliberately, after looking at the
// new picture, with RIDGE_UPDATE_REFERENCE=1.
#include "fixture_archives.h"
#include "read_rgb.h"

#include "ridge/gpu/context.h"
#include "ridge/gpu/render_target.h"
#include "ridge/io/raster_writer.h"
#include "ridge/pipeline/build.h"
#include "ridge/render/terrain_renderer.h"

#include <gdal_priv.h>
#include <gtest/gtest.h>

#include <cstdlib>

using namespace ridge;

namespace {

using test::readRgb;

} // namespace

TEST(ReferenceRender, DefaultViewOfEverestHasSkyAboveTerrainAndMatchesTheReference)
{
    test::ScratchDir scratch;
    const archive::ArchiveReader reader(test::buildEverestArchive(scratch));
    auto context = gpu::HeadlessContext::create();
    render::TerrainRenderer renderer(reader);
    const lod::Viewport vp{320, 180};
    const gpu::RenderTarget target(vp.width, vp.height, 4);
    target.bind();
    renderer.draw(renderer.defaultCamera(vp), {});
    const std::vector<uint8_t> rgba = target.readRgba();
    const std::vector<float> depth = target.readDepth();
    std::vector<uint8_t> rgb(size_t(vp.width) * vp.height * 3);
    for (size_t i = 0; i < rgb.size() / 3; ++i)
        for (int c = 0; c < 3; ++c)
            rgb[3 * i + c] = rgba[4 * i + c];

    // Sky / terrain split from depth (reverse-Z: sky keeps the cleared 0).
    size_t terrain = 0, terrain_in_top_rows = 0;
    for (int y = 0; y < vp.height; ++y)
        for (int x = 0; x < vp.width; ++x) {
            const bool t = depth[size_t(y) * vp.width + x] > 0.f;
            terrain += t;
            terrain_in_top_rows += t && y < vp.height / 25; // the default view's 4 % margin
        }
    const double fraction = double(terrain) / (vp.width * vp.height);
    EXPECT_GT(fraction, 0.12);
    EXPECT_LT(fraction, 0.7);
    EXPECT_EQ(terrain_in_top_rows, 0u) << "the default view frames the terrain below the sky";
    EXPECT_GT(depth[size_t(vp.height / 2) * vp.width + vp.width / 2], 0.f)
        << "terrain at the centre";

    const std::string reference = test::dataPath("render_reference_everest.png");
    if (std::getenv("RIDGE_UPDATE_REFERENCE")) {
        io::writePng(reference, rgb.data(), vp.width, vp.height, 3);
        GTEST_SKIP() << "wrote " << reference;
    }
    int w = 0, h = 0;
    const std::vector<uint8_t> expected = readRgb(reference, w, h);
    ASSERT_FALSE(expected.empty()) << "cannot read " << reference;
    ASSERT_EQ(w, vp.width);
    ASSERT_EQ(h, vp.height);
    double sum = 0.0;
    size_t far_off = 0;
    for (size_t i = 0; i < rgb.size(); i += 3) {
        int worst = 0;
        for (int c = 0; c < 3; ++c) {
            const int d = std::abs(int(rgb[i + c]) - int(expected[i + c]));
            sum += d;
            worst = std::max(worst, d);
        }
        far_off += worst > 48;
    }
    const double mean = sum / double(rgb.size());
    // Rasterisers differ at edges and in the last bits of shading; a broken frame does not
    // stay within these.
    EXPECT_LT(mean, 3.0) << "mean absolute difference per channel";
    EXPECT_LT(double(far_off) / (vp.width * vp.height), 0.02) << "pixels far off the reference";
    if (HasFailure())
        io::writePng("render_reference_actual.png", rgb.data(), vp.width, vp.height,
                     3); // for a look
}
