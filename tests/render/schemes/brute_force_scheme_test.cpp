// Scheme "brute"'s own promise: the finest level everywhere in view, every sample a vertex, so
// that on a lossless archive it draws the data itself.
#include "terrain_renderer_fixture.h"

#include <gtest/gtest.h>

using namespace ridge;

namespace {

class BruteForceScheme : public test::TerrainRendererTest {};

} // namespace

TEST_F(BruteForceScheme, IsWatertightAndDrawsTheFinestSamplesThemselves)
{
    const test::Scene s = scene("lossless", 0.0, {"brute"});
    size_t patches = 0;
    const double worst = worstErrorOverRandomCameras(s, "brute", 2.0, "brute force", patches);
    // Only float rounding of camera-relative heights separates it from the data.
    EXPECT_LT(worst, 0.01) << "brute force draws the finest samples themselves";
    EXPECT_GT(patches, 0u);
}

TEST_F(BruteForceScheme, DrawsTheFinestLevelWhateverEpsilonEverySampleAVertex)
{
    const test::Scene s = scene("lossless", 0.0, {"brute"});
    const int finest = s.reader->geometry().finestLevel();
    const auto cameras = randomCameras(*s.renderer, 4, {320, 180}, 7);
    for (const double epsilon : {1.0, 40.0})
        for (size_t k = 0; k < cameras.size(); ++k) {
            render::RenderSettings settings;
            settings.scheme = "brute";
            settings.epsilon_px = epsilon;
            const render::CapturedSurface surface = s.renderer->capture(cameras[k], settings);
            ASSERT_FALSE(surface.patches.empty());
            for (const PatchId& p : surface.patches)
                EXPECT_EQ(p.level, finest) << "ε " << epsilon << ", camera " << k;
            const GridVertices v = gridVertices(s, surface);
            EXPECT_GT(v.on_grid, v.all * 9 / 10) << "camera " << k;
            EXPECT_EQ(v.off_height, 0u) << "camera " << k;
        }
}
