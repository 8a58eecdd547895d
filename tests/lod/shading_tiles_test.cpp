#include "ridge/lod/shading_tiles.h"

#include "ridge/core/error.h"

#include <gtest/gtest.h>

#include <map>

using namespace ridge;
using namespace ridge::lod;

namespace {

const PyramidGeometry kGeometry(1000, 700, 33); // levels 0..5

// A resident set: patch -> slot; records every patch asked about.
struct FakeResidency {
    std::map<int64_t, int> slots; // by patch index
    mutable std::vector<PatchId> asked;
    void add(PatchId p, int slot) { slots[kGeometry.patchIndex(p)] = slot; }
    int operator()(PatchId p) const
    {
        asked.push_back(p);
        const auto found = slots.find(kGeometry.patchIndex(p));
        return found == slots.end() ? -1 : found->second;
    }
};

ShadingTiles tilesOf(PatchId drawn, const FakeResidency& resident)
{
    ShadingTiles out;
    out.fill(0xdeadbeefu); // every tile must be written
    shadingTiles(drawn, kGeometry, std::cref(resident), out);
    return out;
}

uint32_t at(const ShadingTiles& t, int x, int y)
{
    return t[size_t(y) * kShadingTiles + size_t(x)];
}

} // namespace

TEST(ShadingTiles, NothingFinerResidentShadesFromTheDrawnPatch)
{
    FakeResidency resident;
    resident.add({1, 0, 0}, 7); // the drawn patch's own slot is not a tile's business
    for (uint32_t w : tilesOf({1, 0, 0}, resident))
        EXPECT_EQ(w, 0u);
    for (PatchId p : resident.asked) {
        EXPECT_GT(p.level, 1) << "only descendants are asked about";
        EXPECT_LE(p.level, 1 + kShadingDepth);
    }
}

// Each tile names the finest resident patch over it, however the levels between are resident.
TEST(ShadingTiles, EachTileNamesTheFinestResidentPatchOverIt)
{
    FakeResidency resident;
    resident.add({2, 3, 2}, 4);   // child (1, 0) of drawn (1, 1, 1): tiles x 4..7, y 0..3
    resident.add({3, 7, 4}, 9);   // its child (1, 0): tiles x 6..7, y 0..1
    resident.add({4, 12, 10}, 2); // 3 below, inside (2, 3, 2): one tile, finest there
    resident.add({5, 16, 16}, 3); // 4 levels below: beyond kShadingDepth, never asked
    const ShadingTiles t = tilesOf({1, 1, 1}, resident);
    for (int y = 0; y < kShadingTiles; ++y)
        for (int x = 0; x < kShadingTiles; ++x) {
            uint32_t want = 0u;
            if (x >= 4 && y < 4)
                want = shadingTile(4, 1);
            if (x >= 6 && y < 2)
                want = shadingTile(9, 2);
            // (4, 12, 10): relative to (1,1,1) at level 4, x = 12 − 8 = 4, y = 10 − 8 = 2.
            if (x == 4 && y == 2)
                want = shadingTile(2, 3);
            EXPECT_EQ(at(t, x, y), want) << "tile " << x << ", " << y;
        }
    for (PatchId p : resident.asked)
        EXPECT_LE(p.level, 1 + kShadingDepth);
}

TEST(ShadingTiles, AResidentGrandchildShadesEvenWhereItsParentIsMissing)
{
    FakeResidency resident;
    resident.add({3, 1, 2}, 11); // drawn (1, 0, 0): level 3 x 1, y 2 → tiles x 2..3, y 4..5
    const ShadingTiles t = tilesOf({1, 0, 0}, resident);
    int named = 0;
    for (int y = 0; y < kShadingTiles; ++y)
        for (int x = 0; x < kShadingTiles; ++x) {
            const bool inside = x >= 2 && x <= 3 && y >= 4 && y <= 5;
            EXPECT_EQ(at(t, x, y), inside ? shadingTile(11, 2) : 0u);
            named += inside;
        }
    EXPECT_EQ(named, 4);
}

TEST(ShadingTiles, TheFinestLevelAndTheEdgeOfTheExtentAskNothingThatDoesNotExist)
{
    FakeResidency resident;
    for (uint32_t w : tilesOf({kGeometry.finestLevel(), 3, 2}, resident))
        EXPECT_EQ(w, 0u);
    EXPECT_TRUE(resident.asked.empty());
    // The last column of patches: its right children lie beyond the extent.
    const PatchId edge{2, (kGeometry.patchesX(2)) - 1, 0};
    (void)tilesOf(edge, resident);
    for (PatchId p : resident.asked)
        EXPECT_TRUE(kGeometry.exists(p));
}

TEST(ShadingTiles, TheTileWordKeepsSlotAndDepthApartAndRefusesWhatItCannotHold)
{
    EXPECT_EQ(shadingTile(0, 1), 1u | (1u << 24));
    EXPECT_EQ(shadingTile(41, 3) & 0xffffffu, 42u);
    EXPECT_EQ(shadingTile(41, 3) >> 24, 3u);
    EXPECT_THROW(shadingTile(-1, 1), Error);
    EXPECT_THROW(shadingTile(1 << 24, 1), Error);
    EXPECT_THROW(shadingTile(3, 0), Error);
    EXPECT_THROW(shadingTile(3, kShadingDepth + 1), Error);
}
