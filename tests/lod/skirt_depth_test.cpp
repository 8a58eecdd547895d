#include "ridge/lod/skirt_depth.h"

#include <gtest/gtest.h>

#include <algorithm>

using namespace ridge;
using namespace ridge::lod;

namespace {

PatchQuadtree flatTree()
{
    const PyramidGeometry g(257, 257, 33); // levels 0..3, 8 x 8 finest patches
    std::vector<PatchBounds> bounds(size_t(g.patchCount()));
    for (int64_t i = 0; i < g.patchCount(); ++i)
        bounds[size_t(i)] = {100.f + float(g.patchAt(i).level), 900.f, 10.f};
    return PatchQuadtree(TerrainFrame(g, 1.0, 1.0), std::move(bounds));
}

// A partition: level 1 (0,0) coarse; its east neighbour (1,1,0) split into level 2, one of
// which, (2,2,0), split again into level 3; the south half (1,0,1) and (1,1,1) coarse.
std::vector<PatchId> unbalancedSelection()
{
    return {{1, 0, 0}, {2, 3, 0}, {2, 2, 1}, {2, 3, 1}, {3, 4, 0},
            {3, 5, 0}, {3, 4, 1}, {3, 5, 1}, {1, 0, 1}, {1, 1, 1}};
}

size_t find(const std::vector<PatchId>& s, PatchId p)
{
    return size_t(std::find(s.begin(), s.end(), p) - s.begin());
}

} // namespace

TEST(SkirtDepth, FindsNeighboursAcrossLevelsOnEverySeamAndNoCornerOnlyOnes)
{
    const PatchQuadtree tree = flatTree();
    const std::vector<PatchId> s = unbalancedSelection();
    auto neighbours = [&](PatchId p) {
        std::vector<PatchId> out;
        for (size_t j : seamNeighbours(tree, s, find(s, p)))
            out.push_back(s[j]);
        return out;
    };
    const std::vector<PatchId> coarse = neighbours({1, 0, 0});
    // East: the level-3 patches along x = 4 and the level-2 patch (2,2,1); south: (1,0,1).
    EXPECT_EQ(coarse.size(), 4u);
    for (PatchId p : {PatchId{3, 4, 0}, PatchId{3, 4, 1}, PatchId{2, 2, 1}, PatchId{1, 0, 1}})
        EXPECT_NE(std::find(coarse.begin(), coarse.end(), p), coarse.end());
    // A fine patch sees its coarse west neighbour through the ancestor walk.
    const std::vector<PatchId> fine = neighbours({3, 4, 1});
    EXPECT_NE(std::find(fine.begin(), fine.end(), PatchId{1, 0, 0}), fine.end());
    // (1,1,1) touches (1,0,0) only at a corner: not a seam.
    const std::vector<PatchId> diagonal = neighbours({1, 1, 1});
    EXPECT_EQ(std::find(diagonal.begin(), diagonal.end(), PatchId{1, 0, 0}), diagonal.end());
}

TEST(SkirtDepth, DepthIsThePatchsDeviationPlusItsWorstSeamNeighboursDeviation)
{
    const PatchQuadtree tree = flatTree();
    const std::vector<PatchId> s = unbalancedSelection();
    // Deviation grows with coarseness: 1 m per level above the finest.
    auto deviation = [](PatchId p) { return double(3 - p.level) * 1.0 + 0.5; };
    const std::vector<double> feet = skirtDepths(tree, s, deviation, 0.25);
    ASSERT_EQ(feet.size(), s.size());
    // (3,5,1): neighbours are level 3 and 2 patches (worst: level 2, 1.5 m) — not level 1.
    const size_t a = find(s, {3, 5, 1});
    EXPECT_DOUBLE_EQ(feet[a], 0.5 + 1.5 + 0.25);
    // (3,4,1) borders the level-1 patch to the west: 2.5 m.
    const size_t b = find(s, {3, 4, 1});
    EXPECT_DOUBLE_EQ(feet[b], 0.5 + 2.5 + 0.25);
}
