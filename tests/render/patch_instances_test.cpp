// The instance records of the terrain draw, without GL.
#include "patch_instances.h"

#include "ridge/core/error.h"

#include <gtest/gtest.h>

using namespace ridge;
using namespace ridge::render;

namespace {

// 1000 x 700 samples at 10 m, patches of 33 (cells 32): the last column of patches holds
// samples 992..999 of 1024 (partial), the last row 672..699 of 704.
lod::PatchQuadtree tree()
{
    const PyramidGeometry g(1000, 700, 33);
    std::vector<lod::PatchBounds> bounds(size_t(g.patchCount()));
    for (int64_t i = 0; i < g.patchCount(); ++i)
        bounds[size_t(i)] = {100.f, 300.f, float(g.finestLevel() - g.patchAt(i).level)};
    return lod::PatchQuadtree(lod::TerrainFrame(g, 10.0, 10.0), std::move(bounds));
}

} // namespace

TEST(PatchInstances, WholePatchesComeFirstEachGroupFrontToBack)
{
    const lod::PatchQuadtree t = tree();
    const int L = t.geometry().finestLevel();
    lod::Selection s;
    for (PatchId p : {PatchId{L, 31, 0}, PatchId{L, 0, 0}, PatchId{L, 5, 3}, PatchId{L, 2, 21},
                      PatchId{L, 1, 0}})
        s.patches.push_back({p, 0.0, lod::Visibility::Inside});
    // Camera over the north-west corner (x 0, y at the first row).
    const glm::dvec3 camera(5.0, t.frame().yOf(0) - 5.0, 500.0);
    const PatchInstances r = buildPatchInstances(
        t, s, camera, [](PatchId p) { return p.x; }, [](PatchId) { return 2.0; }, 0.01);
    ASSERT_EQ(r.total(), 5u);
    EXPECT_EQ(r.whole, 3u);
    EXPECT_EQ(r.partial, 2u) << "column 31 and row 21 reach past the valid extent";
    EXPECT_EQ(r.patches[0], (PatchId{L, 0, 0}));
    EXPECT_EQ(r.patches[1], (PatchId{L, 1, 0}));
    EXPECT_EQ(r.patches[2], (PatchId{L, 5, 3}));
    for (size_t k = r.whole; k < r.total(); ++k)
        EXPECT_TRUE(r.patches[k].x == 31 || r.patches[k].y == 21);
    // The partial ones know how far their surface reaches: 999 − 992 = 7 columns, 699 − 672 =
    // 27 rows.
    for (size_t k = 0; k < r.total(); ++k) {
        const GpuPatchInstance& g = r.records[k];
        EXPECT_EQ(g.valid_extent[0], r.patches[k].x == 31 ? 7.f : 32.f);
        EXPECT_EQ(g.valid_extent[1], r.patches[k].y == 21 ? 27.f : 32.f);
        EXPECT_EQ(g.layer, r.patches[k].x);
        EXPECT_FLOAT_EQ(g.min_z, 100.f - 500.f);
        EXPECT_FLOAT_EQ(g.max_z, 300.f - 500.f);
    }
}

TEST(PatchInstances, CoarsePatchesReachTheLastColumnAndRowInsideACell)
{
    // Level L − 2 (step 4) has samples at columns ..., 996, 1000 and rows ..., 696, 700: its
    // last patch column starts at 896 and must draw up to 999, (999 − 896) / 4 = 25.75 cells
    // (26 of them carry its samples, the last one edge-extended); rows from 640 to 699 are
    // 14.75 cells. Level 0 (step 32): 999 / 32 and 699 / 32 cells.
    const lod::PatchQuadtree t = tree();
    const PyramidGeometry& g = t.geometry();
    const int L = g.finestLevel();
    lod::Selection s;
    for (PatchId p : {PatchId{L - 2, 7, 5}, PatchId{L - 2, 6, 5}, PatchId{0, 0, 0}})
        s.patches.push_back({p, 0.0, lod::Visibility::Inside});
    const PatchInstances r = buildPatchInstances(
        t, s, {0, 0, 0}, [](PatchId) { return 0; }, [](PatchId) { return 0.0; }, 0.01);
    ASSERT_EQ(r.whole, 0u);
    for (size_t k = 0; k < r.total(); ++k) {
        const PatchId p = r.patches[k];
        const float x = p.level == 0 ? 999.f / 32 : p.x == 7 ? 25.75f : 32.f;
        const float y = p.level == 0 ? 699.f / 32 : 14.75f;
        EXPECT_EQ(r.records[k].valid_extent[0], x) << p.x;
        EXPECT_EQ(r.records[k].valid_extent[1], y);
    }
    EXPECT_EQ(g.coveredCellsX({L - 2, 7, 5}), 26);
    EXPECT_EQ(g.coveredCellsY({L - 2, 7, 5}), 15);
    EXPECT_EQ(g.coveredCellsX({0, 0, 0}), 32);
    EXPECT_EQ(g.coveredCellsY({0, 0, 0}), 22);
    EXPECT_FALSE(g.whole({L - 2, 6, 5}));
    EXPECT_TRUE(g.whole({L - 2, 6, 4}));
}

TEST(PatchInstances, OriginsAreIntegerSamplesRelativeToTheAnchorNearTheCamera)
{
    const lod::PatchQuadtree t = tree();
    const int L = t.geometry().finestLevel();
    lod::Selection s;
    s.patches.push_back({PatchId{L, 3, 2}, 0.0, lod::Visibility::Inside});
    s.patches.push_back({PatchId{L - 2, 0, 0}, 0.0, lod::Visibility::Inside});
    const glm::dvec3 camera(1234.4, 3456.6, 900.0);
    const CameraAnchor a = cameraAnchor(t.frame(), camera);
    EXPECT_EQ(a.column, 123);
    EXPECT_NEAR(a.x_rel, 1230.0 - 1234.4, 1e-9);
    EXPECT_EQ(a.row, 699 - 346); // y 3456.6 is row 699 − 345.66
    const PatchInstances r = buildPatchInstances(
        t, s, camera, [](PatchId) { return 0; }, [](PatchId) { return 0.0; }, 0.0);
    for (size_t k = 0; k < r.total(); ++k) {
        const PatchId p = r.patches[k];
        const int64_t step = t.geometry().step(p.level);
        EXPECT_EQ(r.records[k].step, step);
        EXPECT_EQ(r.records[k].origin[0], p.x * 32 * step - a.column);
        EXPECT_EQ(r.records[k].origin[1], p.y * 32 * step - a.row);
    }
}

TEST(PatchInstances, AFarCameraOverAFineGridKeepsTheAnchorInRange)
{
    // 1e15 m east over a micrometre grid is 1e21 samples out: beyond int64. The anchor stays
    // 2^40 samples out, so origins are differences that cannot overflow (UBSan would say).
    const PyramidGeometry g(1000, 700, 33);
    const std::vector<lod::PatchBounds> bounds(size_t(g.patchCount()), {0.f, 1.f, 1.f});
    const lod::PatchQuadtree t(lod::TerrainFrame(g, 1e-6, 1e-6), bounds);
    const CameraAnchor a = cameraAnchor(t.frame(), glm::dvec3(1e15, -1e15, 10.0));
    EXPECT_EQ(a.column, int64_t(1) << 40);
    EXPECT_EQ(a.row, int64_t(1) << 40);
    lod::Selection s;
    s.patches.push_back({PatchId{g.finestLevel(), 3, 2}, 0.0, lod::Visibility::Inside});
    const PatchInstances r = buildPatchInstances(
        t, s, glm::dvec3(1e15, -1e15, 10.0), [](PatchId) { return 0; }, [](PatchId) { return 1.0; },
        0.01);
    EXPECT_EQ(r.total(), 1u);
}

TEST(PatchInstances, SkirtDepthsAddTheNeighboursDeviation)
{
    const lod::PatchQuadtree t = tree();
    const int L = t.geometry().finestLevel();
    lod::Selection s;
    s.patches.push_back({PatchId{L, 0, 0}, 0.0, lod::Visibility::Inside}); // Err 0
    s.patches.push_back({PatchId{L, 1, 0}, 0.0, lod::Visibility::Inside}); // Err 0
    const PatchInstances r = buildPatchInstances(
        t, s, {0, 0, 0}, [](PatchId) { return 0; }, [](PatchId p) { return p.x == 0 ? 1.5 : 4.0; },
        0.25);
    for (size_t k = 0; k < 2; ++k)
        EXPECT_FLOAT_EQ(r.records[k].skirt_depth, float(1.5 + 4.0 + 0.25));
}

TEST(PatchInstances, FadingPatchesAreDrawnLastInTheirGroup)
{
    // Only the patches that fade in are drawn with the programs that read their ancestors;
    // grouping them must keep every record with its patch, the whole/clipped split, and the
    // front-to-back order within each part.
    const lod::PatchQuadtree t = tree();
    const int L = t.geometry().finestLevel();
    lod::Selection s;
    for (int x : {0, 1, 2, 3, 31})
        s.patches.push_back({PatchId{L, x, 0}, 0.0, lod::Visibility::Inside});
    const glm::dvec3 camera(5.0, t.frame().yOf(0) - 5.0, 500.0);
    const auto fading = [&](PatchId p) { return p.x == 1 || p.x == 3 || p.x == 31; };
    PatchInstances r = buildPatchInstances(
        t, s, camera, [](PatchId p) { return p.x; }, [](PatchId) { return 0.0; }, 0.01, 1.0,
        [&](PatchId p) -> std::optional<InstanceBlend> {
            if (!fading(p))
                return std::nullopt;
            InstanceBlend b;
            b.chain.depth = 1;
            b.chain.links[0] = {PatchId{L - 1, p.x / 2, 0}, 0.5f};
            b.slots[0] = 100 + p.x;
            return b;
        });
    ASSERT_EQ(r.whole, 4u);
    ASSERT_EQ(r.partial, 1u);
    groupFadingLast(r);
    EXPECT_EQ(r.whole_fading, 2u);
    EXPECT_EQ(r.partial_fading, 1u);
    const std::vector<int> order = {0, 2, 1, 3, 31};
    for (size_t k = 0; k < r.total(); ++k) {
        EXPECT_EQ(r.patches[k].x, order[k]) << k;
        EXPECT_EQ(r.records[k].layer, r.patches[k].x) << "record " << k << " left its patch";
        EXPECT_EQ(r.records[k].fade_weight[0] > 0.f, fading(r.patches[k])) << k;
    }
    const std::array<InstanceGroup, 4> g = instanceGroups(r);
    EXPECT_EQ(g[0].first, 0u);
    EXPECT_EQ(g[0].count, 2u);
    EXPECT_FALSE(g[0].clipped || g[0].fading);
    EXPECT_EQ(g[1].first, 2u);
    EXPECT_EQ(g[1].count, 2u);
    EXPECT_TRUE(g[1].fading && !g[1].clipped);
    EXPECT_EQ(g[2].first, 4u);
    EXPECT_EQ(g[2].count, 0u);
    EXPECT_TRUE(g[2].clipped && !g[2].fading);
    EXPECT_EQ(g[3].first, 4u);
    EXPECT_EQ(g[3].count, 1u);
    EXPECT_TRUE(g[3].clipped && g[3].fading);

    r.records.pop_back();
    EXPECT_THROW(groupFadingLast(r), Error) << "records and patches out of step";
}
