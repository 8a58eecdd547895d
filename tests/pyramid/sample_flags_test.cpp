// Sample flags of every level from one grid (pyramid/sample_flags.h): a coarse sample takes the
// flags of the finest sample at its position, whether the grid is the finest level or a
// streamed build's level L−1 (the finest samples at even positions).
#include "ridge/pyramid/sample_flags.h"

#include <gtest/gtest.h>

#include <random>

using namespace ridge;

namespace {

// Finest flags with runs and isolated samples, deterministic.
std::vector<uint8_t> finestFlags(int w, int h)
{
    std::mt19937 rng(7);
    std::vector<uint8_t> f(size_t(w) * h);
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i)
            f[size_t(j) * w + i] = (i + j) % 11 < 4 ? kSampleWater : uint8_t(rng() % 4);
    return f;
}

} // namespace

TEST(SampleFlagsPyramid, CoarseSamplesTakeTheFinestSampleAtTheirClampedPosition)
{
    const int w = 150, h = 77; // not powers of two: padding at every level
    const PyramidGeometry g(w, h, 17);
    const std::vector<uint8_t> finest = finestFlags(w, h);
    const SampleFlagsPyramid pyramid(SampleFlagsGrid(finest, w, h), g.finestLevel(), g);
    for (int l = 0; l <= g.finestLevel(); ++l) {
        const int64_t s = g.step(l);
        for (int64_t j = 0; j < g.levelHeight(l) + 2; ++j)
            for (int64_t i = 0; i < g.levelWidth(l) + 2; ++i) {
                const int64_t x = std::min<int64_t>(i * s, w - 1),
                              y = std::min<int64_t>(j * s, h - 1);
                ASSERT_EQ(pyramid.at(l, i, j), finest[size_t(y) * w + size_t(x)])
                    << "level " << l << " sample " << i << ", " << j;
            }
    }
}

TEST(SampleFlagsPyramid, AStreamedBuildsLevelAboveTheFinestGivesTheSamePatches)
{
    const int w = 150, h = 77;
    const PyramidGeometry g(w, h, 17);
    const int L = g.finestLevel();
    const std::vector<uint8_t> finest = finestFlags(w, h);
    // Level L−1 as the streamed build materialises it: finest samples at even positions.
    const int cw = g.levelWidth(L - 1), ch = g.levelHeight(L - 1);
    std::vector<uint8_t> coarse(size_t(cw) * ch);
    for (int j = 0; j < ch; ++j)
        for (int i = 0; i < cw; ++i)
            coarse[size_t(j) * cw + i] =
                finest[size_t(std::min(2 * j, h - 1)) * w + std::min(2 * i, w - 1)];
    const SampleFlagsPyramid from_finest(SampleFlagsGrid(finest, w, h), L, g),
        from_coarse(SampleFlagsGrid(coarse, cw, ch), L - 1, g);
    for (int l = 0; l < L; ++l)
        for (int y = 0; y < g.patchesY(l); ++y)
            for (int x = 0; x < g.patchesX(l); ++x) {
                const PatchSampleFlags a = from_finest.patch({l, x, y}),
                                       b = from_coarse.patch({l, x, y});
                EXPECT_EQ(a.kind, b.kind) << l << " " << x << " " << y;
                EXPECT_EQ(a.flags, b.flags) << l << " " << x << " " << y;
            }
}

TEST(SampleFlagsPyramid, UniformPatchesAreCanonical)
{
    const PyramidGeometry g(33, 33, 17);
    std::vector<uint8_t> flags(33 * 33, 0);
    for (int j = 0; j < 33; ++j)
        for (int i = 0; i <= 16; ++i)
            flags[size_t(j) * 33 + i] = kSampleWater; // the west half is water
    const SampleFlagsPyramid pyramid(SampleFlagsGrid(flags, 33, 33), g.finestLevel(), g);
    EXPECT_EQ(pyramid.patch({1, 0, 0}).kind, PatchSampleFlags::Kind::AllWater);
    EXPECT_TRUE(pyramid.patch({1, 0, 0}).flags.empty());
    EXPECT_EQ(pyramid.patch({1, 1, 0}).kind, PatchSampleFlags::Kind::Mixed); // column 16 is water
    EXPECT_EQ(pyramid.patch({0, 0, 0}).kind, PatchSampleFlags::Kind::Mixed);
    const SampleFlagsPyramid none(SampleFlagsGrid(33, 33), g.finestLevel(), g);
    EXPECT_FALSE(none.any());
    EXPECT_EQ(none.patch({0, 0, 0}).kind, PatchSampleFlags::Kind::None);
}

TEST(SampleFlagsPyramid, RefusesAGridOfAnotherSize)
{
    const PyramidGeometry g(33, 33, 17);
    EXPECT_THROW(SampleFlagsPyramid(SampleFlagsGrid(33, 32), g.finestLevel(), g), std::exception);
    EXPECT_THROW(SampleFlagsGrid(std::vector<uint8_t>(33 * 32), 33, 33), std::exception);
}
