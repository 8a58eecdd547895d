#include "ridge/lod/resident_cover.h"

#include "ridge/core/error.h"

#include <gtest/gtest.h>

#include <random>
#include <set>

using namespace ridge;
using namespace ridge::lod;

namespace {

bool isAncestorOrSelf(PatchId a, PatchId p)
{
    while (p.level > a.level)
        p = PatchId{p.level - 1, p.x / 2, p.y / 2};
    return p == a;
}

} // namespace

TEST(ResidentCover, TilesTheSelectionsAreaWithResidentPatchesForRandomResidency)
{
    const PyramidGeometry g(1000, 700, 33);
    std::vector<PatchBounds> bounds(size_t(g.patchCount()));
    for (int64_t i = 0; i < g.patchCount(); ++i)
        bounds[size_t(i)] = {0.f, 500.f, 64.f / float(1 << g.patchAt(i).level)};
    const PatchQuadtree tree(TerrainFrame(g, 10.0, 10.0), bounds);
    std::mt19937 rng(9);
    for (int trial = 0; trial < 50; ++trial) {
        const Camera cam({double(rng() % 10000), double(rng() % 7000), 200.0 + rng() % 2000},
                         {5000, 3500, 0}, 60.0, {1280, 720}, 1.0, 1e6);
        SelectionSettings settings;
        settings.cull = false;
        const Selection sel = tree.select(cam, settings);
        std::set<int64_t> resident{0};
        for (int64_t i = 1; i < g.patchCount(); ++i)
            if (rng() % 3 == 0)
                resident.insert(i);
        const ResidentCover cover =
            residentCover(sel, g, [&](PatchId p) { return resident.count(g.patchIndex(p)) > 0; });
        // Every selected patch lies under exactly one drawn patch, every drawn one is
        // resident, and drawn patches do not overlap.
        int missing = 0;
        for (const SelectedPatch& s : sel.patches) {
            int under = 0;
            for (const SelectedPatch& d : cover.patches)
                under += isAncestorOrSelf(d.id, s.id) || isAncestorOrSelf(s.id, d.id);
            ASSERT_EQ(under, 1) << "trial " << trial;
            missing += !resident.count(g.patchIndex(s.id));
        }
        for (const SelectedPatch& d : cover.patches) {
            EXPECT_TRUE(resident.count(g.patchIndex(d.id)));
            for (const SelectedPatch& e : cover.patches)
                if (!(d.id == e.id)) {
                    EXPECT_FALSE(isAncestorOrSelf(d.id, e.id));
                }
        }
        EXPECT_EQ(cover.missing, missing);
    }
}

TEST(ResidentCover, AllResidentIsTheSelectionItselfAndAMissingRootIsAnError)
{
    const PyramidGeometry g(300, 200, 33);
    std::vector<PatchBounds> bounds(size_t(g.patchCount()), PatchBounds{0.f, 1.f, 1.f});
    const PatchQuadtree tree(TerrainFrame(g, 1.0, 1.0), bounds);
    Selection sel;
    sel.patches.push_back({PatchId{1, 0, 0}, 1.0, Visibility::Inside});
    sel.patches.push_back({PatchId{1, 1, 0}, 1.0, Visibility::Inside});
    const ResidentCover all = residentCover(sel, g, [](PatchId) { return true; });
    EXPECT_EQ(all.patches.size(), 2u);
    EXPECT_EQ(all.missing, 0);
    EXPECT_THROW(residentCover(sel, g, [](PatchId) { return false; }), Error);
}

TEST(ResidentCover, ReusedOutputIsSortedCoarseFirstAndMergesWhatOneAncestorStandsFor)
{
    const PyramidGeometry g(300, 200, 33);
    Selection sel;
    sel.patches.push_back({PatchId{2, 1, 0}, 3.0, Visibility::Inside});
    sel.patches.push_back({PatchId{2, 0, 0}, 5.0, Visibility::Intersecting});
    sel.patches.push_back({PatchId{1, 1, 0}, 1.0, Visibility::Inside});
    // (2, 0, 0) and (2, 1, 0) fall back to (1, 0, 0); the root is resident too.
    const std::set<int> resident_levels_0_1{0, 1};
    ResidentCover cover;
    cover.patches.reserve(8);
    for (int k = 0; k < 2; ++k) { // the second time into the same output
        residentCover(
            sel, g, [&](PatchId p) { return resident_levels_0_1.count(p.level) > 0; }, cover);
        ASSERT_EQ(cover.patches.size(), 2u);
        EXPECT_EQ(cover.patches[0].id, (PatchId{1, 0, 0}));
        EXPECT_EQ(cover.patches[0].screen_error, 5.0);
        EXPECT_EQ(cover.patches[0].visibility, Visibility::Intersecting);
        EXPECT_EQ(cover.patches[1].id, (PatchId{1, 1, 0}));
        EXPECT_EQ(cover.missing, 2);
    }
}
