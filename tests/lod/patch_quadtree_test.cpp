#include "ridge/lod/patch_quadtree.h"
#include "ridge/lod/patch_residency.h"
#include "ridge/lod/screen_space_error.h"

#include "ridge/core/error.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>

using namespace ridge;
using namespace ridge::lod;

namespace {

// A 1000 x 700 sample grid at 10 m, patches of 33: errors halve per level, heights 0..500 m.
PatchQuadtree syntheticTree()
{
    const PyramidGeometry g(1000, 700, 33);
    std::vector<PatchBounds> bounds(size_t(g.patchCount()));
    for (int64_t i = 0; i < g.patchCount(); ++i) {
        const PatchId p = g.patchAt(i);
        const float err = p.level == g.finestLevel() ? 0.f : 64.f / float(1 << p.level);
        bounds[size_t(i)] = {0.f, 500.f, err};
    }
    return PatchQuadtree(TerrainFrame(g, 10.0, 10.0), std::move(bounds));
}

// Finest-cell coverage count of a selection (each cell once = a partition).
std::vector<int> coverage(const PatchQuadtree& tree, const Selection& s)
{
    const PyramidGeometry& g = tree.geometry();
    std::vector<int> count(size_t(g.width() - 1) * (g.height() - 1), 0);
    for (const SelectedPatch& sp : s.patches) {
        const int64_t span = int64_t(g.cells()) * g.step(sp.id.level);
        for (int64_t r = sp.id.y * span;
             r < std::min<int64_t>((sp.id.y + 1) * span, g.height() - 1); ++r)
            for (int64_t c = sp.id.x * span;
                 c < std::min<int64_t>((sp.id.x + 1) * span, g.width() - 1); ++c)
                ++count[size_t(r) * (g.width() - 1) + c];
    }
    return count;
}

Camera overTerrain(glm::dvec3 pos, glm::dvec3 at)
{
    return Camera(pos, at, 60.0, {1280, 720}, 1.0, 1e6);
}

} // namespace

TEST(PatchQuadtree, SelectionWithoutCullingTilesTheValidExtentExactlyOnce)
{
    const PatchQuadtree tree = syntheticTree();
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> x(-2000, 12000), y(-2000, 9000), z(50, 3000);
    for (int k = 0; k < 20; ++k) {
        const Camera cam = overTerrain({x(rng), y(rng), z(rng)}, {5000, 3500, 0});
        SelectionSettings s;
        s.cull = false;
        s.epsilon_px = 1.0 + k;
        const Selection sel = tree.select(cam, s);
        for (int c : coverage(tree, sel))
            ASSERT_EQ(c, 1) << "camera " << k;
    }
}

TEST(PatchQuadtree, EverySelectedPatchMeetsEpsilonAndItsParentDidNot)
{
    const PatchQuadtree tree = syntheticTree();
    const Camera cam = overTerrain({2000, 1000, 300}, {6000, 5000, 0});
    const double gamma = screenSpaceErrorFactor(cam);
    SelectionSettings s;
    s.epsilon_px = 2.0;
    const Selection sel = tree.select(cam, s);
    ASSERT_GT(sel.patches.size(), 10u);
    std::set<int> levels;
    for (const SelectedPatch& sp : sel.patches) {
        levels.insert(sp.id.level);
        const double rho = distanceToBox(cam.position(), tree.box(sp.id));
        const double e = screen_space_error(gamma, tree.bounds(sp.id).err,
                                            visibleDepthBound(cam, tree.box(sp.id), rho));
        // Never below the paper's estimate.
        EXPECT_GE(e, screen_space_error(gamma, tree.bounds(sp.id).err, rho) - 1e-12);
        EXPECT_NEAR(sp.screen_error, e, 1e-9);
        if (sp.id.level < tree.geometry().finestLevel()) {
            EXPECT_LE(e, s.epsilon_px);
        }
        if (sp.id.level > 0) {
            const PatchId parent{sp.id.level - 1, sp.id.x / 2, sp.id.y / 2};
            const double prho = distanceToBox(cam.position(), tree.box(parent));
            EXPECT_GT(screen_space_error(gamma, tree.bounds(parent).err,
                                         visibleDepthBound(cam, tree.box(parent), prho)),
                      s.epsilon_px);
        }
    }
    EXPECT_GE(levels.size(), 3u) << "an oblique view gives an unbalanced tree";
}

TEST(PatchQuadtree, AnErrorScaleOfKIsEpsilonDividedByK)
{
    // Ulrich's chunks simplified to Err(P) have twice its error: selecting them at ε is
    // selecting the patches at ε / 2, and each reports its doubled Err_Scr.
    const PatchQuadtree tree = syntheticTree();
    const Camera cam = overTerrain({2000, 1000, 300}, {6000, 5000, 0});
    SelectionSettings scaled, halved;
    scaled.epsilon_px = 2.0;
    scaled.error_scale = 2.0;
    halved.epsilon_px = 1.0;
    const Selection a = tree.select(cam, scaled), b = tree.select(cam, halved);
    ASSERT_EQ(a.patches.size(), b.patches.size());
    EXPECT_GT(a.patches.size(), tree.select(cam, SelectionSettings{}).patches.size());
    for (size_t k = 0; k < a.patches.size(); ++k) {
        EXPECT_EQ(a.patches[k].id, b.patches[k].id);
        EXPECT_NEAR(a.patches[k].screen_error, 2.0 * b.patches[k].screen_error, 1e-9);
    }
}

TEST(PatchQuadtree, ThePapersDistanceRefinesLessThanTheOffAxisBound)
{
    const PatchQuadtree tree = syntheticTree();
    const Camera cam = overTerrain({2000, 1000, 300}, {6000, 5000, 0});
    SelectionSettings paper, conservative;
    paper.conservative_distance = false;
    const size_t a = tree.select(cam, paper).patches.size(),
                 b = tree.select(cam, conservative).patches.size();
    EXPECT_LT(a, b);
    EXPECT_LT(double(b), 3.0 * a) << "at most about 1/cos(θ_max)² more patches";
}

TEST(PatchQuadtree, CullingDropsOnlyPatchesOutsideTheFrustum)
{
    const PatchQuadtree tree = syntheticTree();
    const Camera cam =
        overTerrain({500, 500, 400}, {9000, 500, 0}); // looking east along the south edge
    SelectionSettings with, without;
    without.cull = false;
    const Selection a = tree.select(cam, with), b = tree.select(cam, without);
    EXPECT_LT(a.patches.size(), b.patches.size());
    EXPECT_GT(a.culled, 0);
    const Frustum f(cam);
    for (const SelectedPatch& sp : a.patches)
        EXPECT_NE(f.classify(tree.box(sp.id)), Visibility::Outside);
    // Every patch of the unculled selection that is visible is also in the culled one.
    std::set<int64_t> kept;
    for (const SelectedPatch& sp : a.patches)
        kept.insert(tree.geometry().patchIndex(sp.id));
    for (const SelectedPatch& sp : b.patches)
        if (f.classify(tree.box(sp.id)) != Visibility::Outside) {
            EXPECT_TRUE(kept.count(tree.geometry().patchIndex(sp.id)));
        }
}

TEST(PatchQuadtree, RaisesEpsilonWhenTheSelectionExceedsThePatchBudget)
{
    const PatchQuadtree tree = syntheticTree();
    const Camera cam = overTerrain({2000, 1000, 100}, {6000, 5000, 0});
    SelectionSettings s;
    s.epsilon_px = 0.5;
    const size_t full = tree.select(cam, s).patches.size();
    s.max_patches = full / 3;
    const Selection limited = tree.select(cam, s);
    EXPECT_LE(limited.patches.size(), s.max_patches);
    EXPECT_GT(limited.epsilon_px, 0.5);
}

TEST(PatchQuadtree, RejectsBoundsThatDoNotMatchTheGeometry)
{
    const PyramidGeometry g(100, 100, 33);
    EXPECT_THROW(PatchQuadtree(TerrainFrame(g, 1, 1), std::vector<PatchBounds>(3)), Error);
}

TEST(TerrainFrame, PutsTheSouthWestCornerAtTheOriginWithYNorth)
{
    const PyramidGeometry g(101, 51, 33);
    const TerrainFrame f(g, 2.0, 3.0);
    EXPECT_DOUBLE_EQ(f.xOf(0), 0.0);
    EXPECT_DOUBLE_EQ(f.yOf(50), 0.0);  // last row is the south edge
    EXPECT_DOUBLE_EQ(f.yOf(0), 150.0); // first row is the north edge
    EXPECT_DOUBLE_EQ(f.rowOf(f.yOf(17)), 17.0);
    const Box root = f.patchBox({0, 0, 0}, -5, 9);
    EXPECT_DOUBLE_EQ(root.max.x, 200.0); // clipped to the valid extent, not the padding
    EXPECT_DOUBLE_EQ(root.min.y, 0.0);
    EXPECT_DOUBLE_EQ(root.max.y, 150.0);
}

TEST(PatchResidency, ReusesResidentPatchesAndEvictsTheLeastRecentlyUsed)
{
    const PyramidGeometry g(1000, 1000, 33);
    PatchResidency r(g, 3);
    const PatchId a{2, 0, 0}, b{2, 1, 0}, c{2, 2, 0}, d{2, 3, 0};
    EXPECT_EQ(r.update({a, b}, 1).size(), 2u);
    EXPECT_EQ(r.update({a, b}, 2).size(), 0u) << "resident patches are not loaded again";
    EXPECT_EQ(r.update({c}, 3).size(), 1u);
    EXPECT_EQ(r.update({a}, 4).size(), 0u);
    // Full: d replaces the least recently used, b (last used at frame 2).
    const auto loads = r.update({d}, 5);
    ASSERT_EQ(loads.size(), 1u);
    EXPECT_EQ(r.slotOf(b), -1);
    EXPECT_EQ(loads[0].slot, 1) << "d takes b's slot";
    EXPECT_GE(r.slotOf(a), 0);
    EXPECT_GE(r.slotOf(c), 0);
    EXPECT_EQ(r.evictions(), 1u);
    EXPECT_EQ(r.residentCount(), 3);
}

TEST(PatchResidency, NeverEvictsAPatchNeededInTheSameFrameAndRejectsOverflow)
{
    const PyramidGeometry g(1000, 1000, 33);
    PatchResidency r(g, 2);
    const PatchId a{2, 0, 0}, b{2, 1, 0}, c{2, 2, 0};
    r.update({a, b}, 1);
    EXPECT_THROW(r.update({a, b, c}, 2), Error);
    EXPECT_EQ(r.update({a, a}, 3).size(), 0u) << "duplicates take no slot";
    r.release(a);
    EXPECT_EQ(r.slotOf(a), -1);
    EXPECT_EQ(r.update({c}, 4).size(), 1u);
    EXPECT_EQ(r.slotOf(b) >= 0, true);
}

TEST(PatchQuadtree, EpsilonZeroSelectsTheFinestLevelAndStillFitsABudget)
{
    const PatchQuadtree tree = syntheticTree();
    const Camera cam = overTerrain({2000, 1000, 300}, {6000, 5000, 0});
    SelectionSettings s;
    s.epsilon_px = 0.0; // brute force
    s.cull = false;
    const Selection all = tree.select(cam, s);
    for (const SelectedPatch& sp : all.patches)
        EXPECT_EQ(sp.id.level, tree.geometry().finestLevel());
    s.max_patches = 5; // raising ε from 0 must terminate
    const Selection limited = tree.select(cam, s);
    EXPECT_LE(limited.patches.size(), 5u);
    EXPECT_GT(limited.epsilon_px, 0.0);
}

// The ancestor of `p` at `level` (<= p.level).
PatchId ancestorAt(PatchId p, int level)
{
    while (p.level > level)
        p = p.parent();
    return p;
}

// Texture detail, decoupled from geometry: with texel_px set the drawn patches are exactly
// geometry's (here Err is 0 everywhere, a flat terrain, so ε keeps the root), and the detail
// below them shows its samples at most texel_px apart on screen unless kShadingDepth or the
// finest level stopped it, with one detail patch per area.
TEST(PatchQuadtree, TexelCriterionWantsDetailBelowTheDrawnPatchesAndDrawsNoMore)
{
    const PyramidGeometry g(1000, 700, 33);
    std::vector<PatchBounds> flat(size_t(g.patchCount()), PatchBounds{0.f, 10.f, 0.f});
    const PatchQuadtree tree(TerrainFrame(g, 10.0, 10.0), std::move(flat));
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> x(-2000, 12000), y(-2000, 9000), z(200, 20000);
    for (int k = 0; k < 20; ++k) {
        const Camera cam = overTerrain({x(rng), y(rng), z(rng)}, {5000, 3500, 0});
        SelectionSettings s;
        const Selection geometric = tree.select(cam, s);
        EXPECT_TRUE(geometric.detail.empty());
        for (const SelectedPatch& sp : geometric.patches)
            EXPECT_EQ(sp.id.level, 0) << "flat: Err 0 keeps the root";
        for (const double texel : {0.5, 1.0, 4.0}) {
            s.texel_px = texel;
            const Selection sel = tree.select(cam, s);
            EXPECT_EQ(sel.texel_px, texel);
            ASSERT_EQ(sel.patches.size(), geometric.patches.size());
            for (size_t j = 0; j < sel.patches.size(); ++j)
                EXPECT_EQ(sel.patches[j].id, geometric.patches[j].id) << "texels draw no more";
            EXPECT_FALSE(sel.detail.empty()) << "camera " << k << " texel " << texel;
            for (const SelectedPatch& sp : sel.detail) {
                const int below = sp.id.level - geometric.patches[0].id.level;
                EXPECT_GE(below, 1);
                EXPECT_LE(below, kShadingDepth);
                if (below < kShadingDepth && sp.id.level < g.finestLevel()) {
                    EXPECT_LE(sp.texel_spacing, texel) << "camera " << k;
                }
                // The bound is the same γ·s/ρ' as Err_Scr's: recompute it from the box.
                const Box b = tree.box(sp.id);
                const double depth = visibleDepthBound(cam, b, distanceToBox(cam.position(), b));
                EXPECT_DOUBLE_EQ(sp.texel_spacing,
                                 projectedSampleSpacing(screenSpaceErrorFactor(cam),
                                                        10.0 * double(g.step(sp.id.level)), depth));
                // Refined because its parent's texels were too coarse.
                const Box pb = tree.box(sp.id.parent());
                EXPECT_GT(projectedSampleSpacing(
                              screenSpaceErrorFactor(cam), 10.0 * double(g.step(sp.id.level - 1)),
                              visibleDepthBound(cam, pb, distanceToBox(cam.position(), pb))),
                          texel);
            }
            // Without culling, the detail and the drawn patches without detail tile the
            // extent exactly once.
            SelectionSettings all = s;
            all.cull = false;
            const Selection whole = tree.select(cam, all);
            Selection shading;
            shading.patches = whole.detail;
            for (const SelectedPatch& d : whole.patches)
                if (std::none_of(whole.detail.begin(), whole.detail.end(),
                                 [&](const SelectedPatch& q) {
                                     return ancestorAt(q.id, d.id.level) == d.id;
                                 }))
                    shading.patches.push_back(d);
            for (int c : coverage(tree, shading))
                ASSERT_EQ(c, 1) << "camera " << k << " texel " << texel;
        }
    }
}

// Drawn patches first: ε is raised until they fit max_patches, then the texel target until
// the detail fits beside them.
TEST(PatchQuadtree, TexelTargetIsRaisedUntilTheDetailFitsBesideTheDrawnPatches)
{
    const PyramidGeometry g(1000, 700, 33);
    std::vector<PatchBounds> flat(size_t(g.patchCount()), PatchBounds{0.f, 10.f, 0.f});
    const PatchQuadtree tree(TerrainFrame(g, 10.0, 10.0), std::move(flat));
    SelectionSettings s;
    s.texel_px = 0.25;
    s.max_patches = 6;
    const Camera cam = overTerrain({5000, -500, 800}, {5000, 3500, 0});
    const Selection sel = tree.select(cam, s);
    EXPECT_EQ(sel.epsilon_px, s.epsilon_px) << "the root alone is drawn: ε is met";
    EXPECT_LE(sel.patches.size() + sel.detail.size(), 6u);
    EXPECT_FALSE(sel.detail.empty());
    EXPECT_GT(sel.texel_px, 0.25);
    s.max_patches = 1; // room for the drawn patch alone
    const Selection bare = tree.select(cam, s);
    EXPECT_EQ(bare.patches.size(), 1u);
    EXPECT_TRUE(bare.detail.empty());
    s.texel_px = -1.0;
    EXPECT_THROW(tree.select(cam, s), Error);
    s.texel_px = std::nan("");
    EXPECT_THROW(tree.select(cam, s), Error);
}
