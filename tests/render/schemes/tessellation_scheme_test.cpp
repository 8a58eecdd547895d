// Scheme "tess"'s own promises at the terrain's clipped east and south borders: tessellated
// coarse levels reach the border and stay closed there, over relief and over a flat sea.
#include "terrain_border_checks.h"

#include <gtest/gtest.h>

using namespace ridge;

namespace {

class TessellationScheme : public test::TerrainRendererTest {};

} // namespace

TEST_F(TessellationScheme, CoarseLevelsReachTheEastAndSouthBorder)
{
    // Everest is 301 x 203: W − 1 = 300 and H − 1 = 202 are multiples of neither 8 nor 16,
    // the steps of its coarse levels with patches of 33 (5 levels) and 65 (4 levels).
    for (const int patch_size : {33, 65}) {
        const std::string name = "tessellation, patches of " + std::to_string(patch_size);
        test::Scene s =
            test::openScene(test::buildEverestArchive(*scratch_, "lossless", patch_size), "tess");
        const test::Counts n = test::checkBorders(s, name);
        // The cameras must draw levels that end short of the border, or nothing was tested.
        EXPECT_GE(n.short_borders, 2u) << name;
    }
}

TEST_F(TessellationScheme, FlatSeaPatchesAreClosed)
{
    // Tessellated skirts over the sea hang λ = 0 plus the margin.
    test::Scene s = test::openScene(test::seaArchive(*scratch_), "tess");
    const test::Counts n = test::checkBorders(s, "sea, tessellation");
    EXPECT_GE(n.short_borders, 4u);
    // With the texture-detail criterion flat sea patches of different levels meet, closed by
    // skirts as thin as float rounding allows.
    test::checkBorders(s, "sea, tessellation, texel 1 px", 1.0);
}
