// The rings structure and selector (lod/rings.h), without GL: updateRings' toroidal array,
// the paper's stitch table against the stitching the tiles' levels ask for, the streaming
// cover's invariants under random residency, fitting the slots, and hostile cameras.
#include "ridge/lod/rings.h"

#include "ridge/core/error.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <random>
#include <set>

using namespace ridge;
using namespace ridge::lod;

namespace {

// A 2049 × 1537 grid of 65-sample patches: 32 × 24 tiles, 6 levels below the root.
struct Terrain {
    PyramidGeometry g{2049, 1537, 65};
    PatchQuadtree tree = make(g);

    static PatchQuadtree make(const PyramidGeometry& g)
    {
        std::vector<PatchBounds> bounds(size_t(g.patchCount()));
        for (int64_t i = 0; i < g.patchCount(); ++i) {
            const PatchId p = g.patchAt(i);
            bounds[size_t(i)] = {float(p.x % 7) * 10.f, 400.f + float(p.y % 5) * 30.f,
                                 32.f / float(1 << p.level)};
        }
        return PatchQuadtree(TerrainFrame(g, 30.0, 30.0), bounds);
    }
    // A camera above tile (tx, ty), looking at `at` (terrain-frame metres).
    Camera above(double tx, double ty, double height, glm::dvec3 at) const
    {
        const double span = 64.0 * 30.0;
        const glm::dvec3 pos((tx + 0.5) * span, tree.frame().extentY() - (ty + 0.5) * span, height);
        return Camera(pos, at, 60.0, {640, 360}, 1.0, 1e7);
    }
};

int levelDifference(const RingTile& a, const RingTile& b)
{
    return std::abs(a.level - b.level);
}

} // namespace

TEST(Rings, LevelsFallOneARingOutsideTheFirstAndTheOutermostRingReachesTheEdge)
{
    Terrain t;
    RingsStructure s(t.tree, RingsSettings{4, 1});
    s.updateRings(10, 10);
    EXPECT_EQ(s.finestLevel(), 5);
    EXPECT_EQ(s.levelOfRing(0), 5); // the central patch
    EXPECT_EQ(s.levelOfRing(1), 5); // the first ring shares its level
    EXPECT_EQ(s.levelOfRing(2), 4);
    EXPECT_EQ(s.levelOfRing(4), 2);
    EXPECT_EQ(s.levelOfRing(30), 2); // beyond the last ring: its level
    EXPECT_EQ(s.levelOfRing(2, 3), 1);
    EXPECT_EQ(s.levelOfRing(4, 9), 0);
    EXPECT_EQ(s.cellsAt(5), 64);
    EXPECT_EQ(s.cellsAt(2), 8);
    EXPECT_EQ(s.ringOf(13, 8), 3);
    EXPECT_EQ(s.orientationOf(13, 8), Orientation::East);
    EXPECT_EQ(s.orientationOf(13, 7), Orientation::NorthEast);
    EXPECT_EQ(s.orientationOf(9, 7), Orientation::North);
    EXPECT_EQ(s.orientationOf(7, 13), Orientation::SouthWest);
    // Default: one ring per level, the last at the root.
    RingsStructure all(t.tree, RingsSettings{});
    EXPECT_EQ(all.rings(), 6);
    EXPECT_EQ(all.levelOfRing(6), 0);
}

TEST(Rings, UpdateRingsRefreshesOnlyTheCellsThatWrap)
{
    Terrain t;
    RingsStructure s(t.tree, RingsSettings{3, 1});
    s.updateRings(12, 12);
    const int w = s.window();
    EXPECT_EQ(s.cellsRefreshed(), w * w); // first call: every cell
    s.updateRings(13, 12);                // east neighbour: one column wraps
    EXPECT_EQ(s.cellsRefreshed(), w);
    s.updateRings(12, 11); // north-west: a row and a column
    EXPECT_EQ(s.cellsRefreshed(), 2 * w - 1);
    s.updateRings(12, 11); // the same centre: nothing
    EXPECT_EQ(s.cellsRefreshed(), 0);
    s.updateRings(20, 3); // a jump: everything
    EXPECT_EQ(s.cellsRefreshed(), w * w);
    // Every cell of the window holds its own tile, ring and orientation.
    for (int y = s.centreY() - 3; y <= s.centreY() + 3; ++y)
        for (int x = s.centreX() - 3; x <= s.centreX() + 3; ++x) {
            const RingCell& c = s.cell(x, y);
            EXPECT_EQ(c.tile_x, x);
            EXPECT_EQ(c.tile_y, y);
            EXPECT_EQ(c.ring, s.ringOf(x, y));
            EXPECT_EQ(c.orientation, s.orientationOf(x, y));
            EXPECT_EQ(c.exists, x >= 0 && y >= 0 && x < s.tilesX() && y < s.tilesY());
        }
    EXPECT_THROW(s.cell(s.centreX() + 4, s.centreY()), Error);
}

TEST(Rings, TheStitchTableIsWhatTheNeighboursLevelsAskFor)
{
    // With every patch resident, each tile away from the border draws its ring's level and
    // the paper's table must give exactly the stitching its neighbours' levels require.
    Terrain t;
    for (int rings : {2, 4, 6})
        for (int step : {1, 2}) {
            RingsSelector selector(t.tree, RingsSettings{rings, step});
            SelectionSettings settings;
            settings.cull = false;
            Selection desired;
            selector.select(t.above(15, 11, 500.0, {0, 0, 0}), settings, desired);
            ResidentCover cover;
            selector.cover(
                desired, [](PatchId) { return true; }, cover);
            int by_table = 0, stitched = 0;
            for (const RingTile& tile : selector.drawnTiles()) {
                EXPECT_EQ(tile.level, selector.structure().levelOfRing(tile.ring));
                if (!tile.by_table)
                    continue;
                ++by_table;
                stitched += tile.stitch != 0;
                EXPECT_EQ(tile.stitch, kStitchTable[size_t(tile.orientation)])
                    << "tile " << tile.x << "," << tile.y << " ring " << tile.ring;
            }
            EXPECT_GT(by_table, 300);
            EXPECT_GE(stitched, 8 * std::min(rings - 1, 4)) << rings;
        }
}

TEST(Rings, TheStreamingCoverNeverPutsTwoLevelsAcrossAnEdgeAndReadsOnlyResidentPatches)
{
    Terrain t;
    const PyramidGeometry& g = t.g;
    std::mt19937 rng(5);
    RingsSelector selector(t.tree, RingsSettings{5, 1});
    for (int trial = 0; trial < 60; ++trial) {
        const Camera cam = t.above(rng() % 32, rng() % 24, 300.0 + rng() % 3000,
                                   {double(rng() % 60000), double(rng() % 45000), 0.0});
        SelectionSettings settings;
        settings.cull = trial % 3 != 0;
        Selection desired;
        selector.select(cam, settings, desired);
        std::set<int64_t> resident{0};
        for (const SelectedPatch& p : desired.patches)
            if (rng() % 2)
                resident.insert(g.patchIndex(p.id));
        for (int64_t i = 1; i < g.patchCount(); ++i)
            if (rng() % 9 == 0)
                resident.insert(i);
        auto isResident = [&](PatchId p) { return resident.count(g.patchIndex(p)) > 0; };
        ResidentCover cover;
        selector.cover(desired, isResident, cover);
        const std::vector<RingTile>& tiles = selector.drawnTiles();
        ASSERT_FALSE(tiles.empty());
        std::set<int64_t> listed;
        for (const SelectedPatch& p : cover.patches)
            listed.insert(g.patchIndex(p.id));
        std::map<std::pair<int, int>, const RingTile*> at;
        for (const RingTile& tile : tiles)
            at[{tile.x, tile.y}] = &tile;
        for (const RingTile& tile : tiles) {
            const PatchId own = selector.ancestorOf(tile.x, tile.y, tile.level);
            EXPECT_TRUE(isResident(own));
            EXPECT_TRUE(listed.count(g.patchIndex(own))) << "the cover must keep what it draws";
            if (tile.stitch) {
                const PatchId coarse = selector.ancestorOf(tile.x, tile.y, tile.level - 1);
                EXPECT_TRUE(isResident(coarse));
                EXPECT_TRUE(listed.count(g.patchIndex(coarse)));
            }
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    auto it = at.find({tile.x + dx, tile.y + dy});
                    if (it == at.end())
                        continue;
                    const RingTile& u = *it->second;
                    ASSERT_LE(levelDifference(tile, u), 1) << "trial " << trial;
                    // The finer of two edge neighbours stitches the shared edge.
                    if (u.level < tile.level && (dx == 0) != (dy == 0)) {
                        const EdgePosition e = dy < 0   ? EdgePosition::Up
                                               : dx > 0 ? EdgePosition::Right
                                               : dy > 0 ? EdgePosition::Down
                                                        : EdgePosition::Left;
                        EXPECT_TRUE(tile.stitch & edgeBit(e));
                    }
                }
        }
        EXPECT_EQ(cover.missing, selector.lowered());
    }
}

TEST(Rings, ManyMorePatchesThanSlotsDrawEveryRingCoarser)
{
    Terrain t;
    RingsSelector selector(t.tree, RingsSettings{6, 1});
    SelectionSettings settings;
    settings.cull = false;
    Selection all, few;
    selector.select(t.above(16, 12, 400.0, {0, 0, 0}), settings, all);
    EXPECT_EQ(all.levels_coarser, 0);
    settings.max_patches = 12;
    selector.select(t.above(16, 12, 400.0, {0, 0, 0}), settings, few);
    EXPECT_GT(few.levels_coarser, 0);
    EXPECT_LE(few.patches.size(), 12u);
    EXPECT_GT(all.patches.size(), few.patches.size());
    // Inner rings rank first within a level.
    for (const SelectedPatch& p : all.patches)
        EXPECT_GE(p.rank, 1.0);
}

TEST(Rings, CamerasFarOffTheTerrainCentreOnItsEdgeWithoutLeavingTheArray)
{
    Terrain t;
    RingsSelector selector(t.tree, RingsSettings{3, 2});
    SelectionSettings settings;
    const double big = 1e12;
    for (glm::dvec3 pos :
         {glm::dvec3(-big, -big, 100.0), glm::dvec3(big, big, 1e9), glm::dvec3(big, -big, -big),
          glm::dvec3(-big, big, 1.0), glm::dvec3(9.9e14, 0.0, 10.0)}) {
        const Camera cam(pos, pos + glm::dvec3(1.0, 1.0, -1.0), 60.0, {320, 200}, 1.0, 1e7);
        Selection desired;
        ASSERT_NO_THROW(selector.select(cam, settings, desired));
        const RingsStructure& s = selector.structure();
        EXPECT_TRUE(s.centreX() == 0 || s.centreX() == s.tilesX() - 1);
        EXPECT_TRUE(s.centreY() == 0 || s.centreY() == s.tilesY() - 1);
        ResidentCover cover;
        selector.cover(
            desired, [](PatchId p) { return p.level == 0; }, cover);
        for (const RingTile& tile : selector.drawnTiles())
            EXPECT_EQ(tile.level, 0);
    }
}

TEST(Rings, SettingsThePatchSizeCannotTakeAreRefusedNamingTheOption)
{
    Terrain t;
    auto message = [&](RingsSettings s) {
        try {
            s.validate(t.g);
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    EXPECT_NE(message({17, 1}).find("rings=17"), std::string::npos);
    EXPECT_NE(message({-1, 1}).find("rings=-1"), std::string::npos);
    EXPECT_NE(message({2, 3}).find("vertex-step=3"), std::string::npos);
    EXPECT_EQ(message({16, 2}), "");
    // 16 385² samples in 17-sample patches: 1024 tiles a side, 11 levels; a 16-cell grid
    // cannot draw a tile at the root.
    const PyramidGeometry deep(16385, 16385, 17);
    const std::string m = [&] {
        try {
            RingsSettings{4, 1}.validate(deep);
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string();
    }();
    EXPECT_NE(m.find("patches of 17 samples"), std::string::npos) << m;
}

namespace {

// A whole-Earth grid of `turn` columns a turn (one more: the repeated edge meridian), rows
// from pole to pole, patches of `patch` samples, with flat bounds.
PatchQuadtree wrappingGlobe(int turn, int patch = 17)
{
    const int rows = turn / 2 + 1;
    GeodeticGrid grid;
    grid.lon0 = 0.0;
    grid.lat0 = std::numbers::pi / 2;
    grid.dlon = 2.0 * std::numbers::pi / turn;
    grid.dlat = -grid.dlon;
    grid.wrap_columns = turn;
    const PyramidGeometry g(turn + 1, rows, patch);
    std::vector<PatchBounds> bounds(size_t(g.patchCount()), PatchBounds{0.f, 100.f, 1.f});
    return PatchQuadtree(TerrainFrame::ellipsoid(g, 1.0, 1.0, grid), bounds);
}

} // namespace

// On a globe that goes round the Earth the tiles wrap: the column west of tile 0 is the last
// tile, one ring out, and rings, orientations and the window are measured the short way round.
TEST(Rings, TilesWrapRoundAGlobeWhoseTurnIsWholeTiles)
{
    const PatchQuadtree tree = wrappingGlobe(256); // 16 tiles of 16 columns a turn
    EXPECT_EQ(ringsWrapTiles(tree.frame()), 16);
    RingsStructure s(tree, RingsSettings{});
    ASSERT_EQ(s.wrapTiles(), 16);
    s.updateRings(0, 3);
    EXPECT_EQ(s.columnAt(0, -1), 15);
    EXPECT_EQ(s.columnAt(15, 1), 0);
    EXPECT_EQ(s.ringOf(15, 3), 1);
    EXPECT_EQ(s.orientationOf(15, 3), Orientation::West);
    EXPECT_EQ(s.orientationOf(15, 2), Orientation::NorthWest);
    EXPECT_EQ(s.ringOf(8, 3), 8); // the antipode: the farthest column either way
    // The window holds the tiles across the seam: the west ones are the last columns.
    EXPECT_EQ(s.cell(15, 3).tile_x, 15);
    EXPECT_EQ(s.cell(14, 3).tile_x, 14);
    EXPECT_TRUE(s.cell(15, 3).exists);
    // Moving across the seam is a move to a neighbour: one column of cells is refreshed.
    s.updateRings(15, 3);
    EXPECT_EQ(s.cellsRefreshed(), s.window());
    EXPECT_EQ(s.ringOf(0, 3), 1);
    EXPECT_EQ(s.orientationOf(0, 3), Orientation::East);
}

TEST(Rings, AGlobeWhoseTurnIsNotWholeTilesIsRefusedSayingWhatWouldDo)
{
    const PatchQuadtree tree = wrappingGlobe(180); // 16-column tiles, 11.25 a turn
    try {
        RingsStructure s(tree, RingsSettings{});
        ADD_FAILURE() << "a turn of 11.25 tiles was accepted";
    } catch (const Error& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("180"), std::string::npos) << m;
        // 4 divides 180 but a grid of 4-column tiles has too many levels for the root to be a
        // tile: no patch size will do, and the message says so.
        EXPECT_NE(m.find("no patch size"), std::string::npos) << m;
    }
    // 384 columns a turn (3 · 2^7) in 257-sample patches (1.5 tiles): 128-column tiles would
    // divide it and reach the root.
    try {
        RingsStructure s(wrappingGlobe(384, 257), RingsSettings{});
        ADD_FAILURE() << "a turn of 1.5 tiles was accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("--patch 129"), std::string::npos) << e.what();
    }
    // A plane never wraps.
    EXPECT_EQ(ringsWrapTiles(Terrain{}.tree.frame()), 0);
}
