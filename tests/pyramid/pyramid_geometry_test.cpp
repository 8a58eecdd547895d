#include "ridge/core/error.h"
#include "ridge/pyramid/pyramid_geometry.h"

#include <gtest/gtest.h>

using namespace ridge;

TEST(PyramidGeometry, LevelZeroIsOnePatchCoveringTheWholeGrid)
{
    const PyramidGeometry g(1201, 1201, 129);
    EXPECT_EQ(g.levelCount(), 5); // 128 * 2^4 = 2048 >= 1200
    EXPECT_EQ(g.patchCount(0), 1);
    EXPECT_GE(int64_t{g.cells()} * g.step(0), 1200);
}

TEST(PyramidGeometry, NonSquareGridsOnlyGetPatchesTouchingTheValidExtent)
{
    const PyramidGeometry g(10801, 4801, 129);
    const int l = g.finestLevel();
    EXPECT_EQ(g.patchesX(l), 85); // ceil(10800 / 128)
    EXPECT_EQ(g.patchesY(l), 38); // ceil(4800 / 128)
    EXPECT_EQ(g.levelWidth(l), 10801);
    EXPECT_EQ(g.validLevelWidth(l - 1), 5401);
    int64_t total = 0;
    for (int k = 0; k < g.levelCount(); ++k)
        total += g.patchCount(k);
    EXPECT_EQ(total, g.patchCount());
}

TEST(PyramidGeometry, PatchIndexRoundTrips)
{
    const PyramidGeometry g(301, 203, 33);
    for (int64_t i = 0; i < g.patchCount(); ++i) {
        const PatchId p = g.patchAt(i);
        ASSERT_TRUE(g.exists(p));
        ASSERT_EQ(g.patchIndex(p), i);
    }
}

TEST(PyramidGeometry, EveryLevelSampleInsideTheExtentIsCoveredByAPatch)
{
    const PyramidGeometry g(301, 203, 17);
    for (int l = 0; l < g.levelCount(); ++l) {
        EXPECT_GE(int64_t{g.patchesX(l)} * g.cells() + 1, g.levelWidth(l));
        EXPECT_GE(int64_t{g.patchesY(l)} * g.cells() + 1, g.levelHeight(l));
        EXPECT_GE((g.levelWidth(l) - 1) * g.step(l), g.width() - 1);
    }
}

TEST(PyramidGeometry, RejectsPatchSizesThatAreNotPowerOfTwoPlusOne)
{
    EXPECT_THROW(PyramidGeometry(100, 100, 128), Error);
    EXPECT_THROW(PyramidGeometry(100, 100, 3), Error);
    EXPECT_THROW(PyramidGeometry(1, 100, 129), Error);
}
