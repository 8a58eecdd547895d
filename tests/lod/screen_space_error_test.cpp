#include "ridge/lod/edge_tessellation.h"
#include "ridge/lod/frustum.h"
#include "ridge/lod/screen_space_error.h"

#include <glm/common.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace ridge::lod;

namespace {
Camera lookingNorth(Viewport v = {1920, 1080}, double fov = 60.0)
{
    return Camera({0.0, 0.0, 100.0}, {0.0, 1000.0, 100.0}, fov, v, 1.0, 1e5);
}
} // namespace

TEST(ScreenSpaceError, GammaIsHalfTheLargerOfBothAxesCotangentTerms)
{
    const Camera c = lookingNorth({1920, 1080}, 60.0);
    const double rh = 1920.0 / std::tan(c.fovX() / 2), rv = 1080.0 / std::tan(c.fovY() / 2);
    EXPECT_NEAR(screenSpaceErrorFactor(c), 0.5 * std::max(rh, rv), 1e-9);
    EXPECT_NEAR(screenSpaceErrorFactor(c), 0.5 * 1080.0 / std::tan(M_PI / 6), 1e-6);
}

TEST(ScreenSpaceError, EqualsTheProjectedLengthOfAnErrorSeenFaceOnAtTheScreenCentre)
{
    const Camera c = lookingNorth();
    const double gamma = screenSpaceErrorFactor(c);
    for (double rho : {10.0, 250.0, 4000.0}) {
        const double err = 3.0;
        const double projected =
            projectedVerticalSegment(c.viewProjection(), c.viewport(), {0.0, rho, 0.0}, err);
        EXPECT_NEAR(screen_space_error(gamma, err, rho), projected, projected * 1e-6) << rho;
    }
}

TEST(ScreenSpaceError, TheVisibleDepthBoundHoldsForVerticalErrorsAnywhereOnScreen)
{
    // Looking steeply down, a vertical error near the screen's corner is seen almost
    // side-on at a depth below its distance: it projects longer than γ·e / depth. The bound
    // must still hold for every visible point of a box.
    const Camera cam({0, 0, 1000}, {0, 300, 0}, 60.0, {1280, 720}, 1.0, 1e5);
    const double gamma = screenSpaceErrorFactor(cam);
    const glm::dmat4 vp = cam.viewProjection();
    const Frustum frustum(cam);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    double worst = 0.0;
    for (int k = 0; k < 2000; ++k) {
        const glm::dvec3 lo(-1500 + 3000 * u(rng), -1500 + 3000 * u(rng), 0.0);
        const Box box{lo, lo + glm::dvec3(200, 200, 50)};
        const double rho = distanceToBox(cam.position(), box);
        const double bound = screen_space_error(gamma, 1.0, visibleDepthBound(cam, box, rho));
        for (int i = 0; i < 27; ++i) {
            const glm::dvec3 p =
                box.min + (box.max - box.min) * glm::dvec3(i % 3, i / 3 % 3, i / 9) * 0.5;
            const glm::dvec4 q = vp * glm::dvec4(p - cam.position(), 1.0);
            if (std::abs(q.x) > q.w || std::abs(q.y) > q.w || q.w < cam.nearPlane())
                continue;
            const double px = projectedVerticalSegment(vp, cam.viewport(), p - cam.position(), 1.0);
            EXPECT_LE(px, bound * 1.0001) << k;
            worst = std::max(worst, px / bound);
        }
    }
    EXPECT_GT(worst, 0.5) << "the cases must come near the bound";
}

TEST(ScreenSpaceError, IsInfiniteInsideTheBoxAndZeroForExactPatches)
{
    EXPECT_TRUE(std::isinf(screen_space_error(900.0, 1.0, 0.0)));
    EXPECT_EQ(screen_space_error(900.0, 0.0, 0.0), 0.0);
}

TEST(ScreenSpaceError, DistanceToBoxIsToTheClosestPoint)
{
    const Box b{{0, 0, 0}, {10, 20, 5}};
    EXPECT_EQ(distanceToBox({5, 5, 2}, b), 0.0);
    EXPECT_DOUBLE_EQ(distanceToBox({13, 5, 2}, b), 3.0);
    EXPECT_DOUBLE_EQ(distanceToBox({13, 24, 5}, b), 5.0);
    EXPECT_DOUBLE_EQ(distanceToBox({5, 5, 17}, b), 12.0);
}

TEST(Frustum, ClassifiesBoxesAheadBehindAndAcrossTheSides)
{
    const Frustum f(lookingNorth());
    EXPECT_EQ(f.classify({{-5, 100, 95}, {5, 110, 105}}), Visibility::Inside);
    EXPECT_EQ(f.classify({{-5, -110, 95}, {5, -100, 105}}), Visibility::Outside);
    EXPECT_EQ(f.classify({{-5, -10, 95}, {5, 10, 105}}), Visibility::Intersecting);
    EXPECT_EQ(f.classify({{5000, 100, 95}, {5010, 110, 105}}), Visibility::Outside);
    EXPECT_EQ(f.classify({{-5, 2e5, 95}, {5, 2e5 + 10, 105}}), Visibility::Outside); // past far
}

// The n/p-vertex test must be conservative: "outside" only when no point of the box is
// visible, "inside" only when every point is. Checked against clip-space tests of points.
TEST(Frustum, NeverCullsAVisiblePointAndInsideMeansEveryCornerInside)
{
    const Camera cam({300, -200, 400}, {0, 500, 0}, 50.0, {800, 600}, 1.0, 3000.0);
    const Frustum f(cam);
    const glm::dmat4 vp = cam.viewProjection();
    auto visible = [&](glm::dvec3 p) {
        const glm::dvec4 q = vp * glm::dvec4(p - cam.position(), 1.0);
        return std::abs(q.x) <= q.w && std::abs(q.y) <= q.w && std::abs(q.z) <= q.w;
    };
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> pos(-2000, 2000), size(1, 600);
    int outside = 0, inside = 0;
    for (int k = 0; k < 2000; ++k) {
        glm::dvec3 lo(pos(rng), pos(rng) + 1000, pos(rng) * 0.25);
        const Box box{lo, lo + glm::dvec3(size(rng), size(rng), size(rng))};
        const Visibility v = f.classify(box);
        bool any = false, all = true;
        for (int s = 0; s < 343; ++s) {
            const glm::dvec3 t((s % 7) / 6.0, (s / 7 % 7) / 6.0, (s / 49) / 6.0);
            const bool in = visible(box.min + t * (box.max - box.min));
            any |= in;
            all &= in;
        }
        if (v == Visibility::Outside) {
            ++outside;
            EXPECT_FALSE(any) << k;
        }
        if (v == Visibility::Inside) {
            ++inside;
            EXPECT_TRUE(all) << k;
        }
    }
    EXPECT_GT(outside, 100);
    EXPECT_GT(inside, 10);
}

TEST(EdgeTessellation, SharedEdgeErrorsAreTheMaximumOfBothBlocksAndSymmetric)
{
    const EdgeErrors a{{1, 2, 8, 3}, 0.5f}, b{{2, 1, 4, 9}, 0.5f};
    const EdgeErrors ab = sharedEdgeErrors(a, b, 4), ba = sharedEdgeErrors(b, a, 4);
    for (int d = 0; d < 4; ++d) {
        EXPECT_EQ(ab.lambda[d], std::max(a.lambda[d], b.lambda[d]));
        EXPECT_EQ(ab.lambda[d], ba.lambda[d]);
    }
    EXPECT_EQ(ab.patch_error, 0.5f);
}

TEST(EdgeTessellation, PicksTheLargestSimplificationWhoseProjectedErrorStaysBelowEpsilon)
{
    const Camera c = lookingNorth();
    const glm::dmat4 vp = c.viewProjection();
    const EdgeErrors e{{0.5f, 1.0f, 2.0f, 4.0f}};
    const glm::dvec3 centre(0, 500, -100); // 500 m ahead, camera-relative
    for (double eps : {0.1, 1.0, 2.0, 4.0, 8.0, 50.0}) {
        const int d = edgeSimplification(vp, c.viewport(), centre, e, 4, eps);
        // Brute force over the definition.
        int expect = 0;
        for (int k = 1; k <= 4; ++k)
            if (projectedVerticalSegment(vp, c.viewport(), centre, e.lambda[k - 1]) < eps)
                expect = k;
        EXPECT_EQ(d, expect) << eps;
        if (d > 0) {
            EXPECT_LT(projectedVerticalSegment(vp, c.viewport(), centre, e.lambda[d - 1]), eps);
        }
    }
    EXPECT_EQ(edgeSimplification(vp, c.viewport(), centre, e, 4, 1e6), 4);
    EXPECT_EQ(edgeSimplification(vp, c.viewport(), centre, e, 2, 1e6), 2); // D limits d
    EXPECT_EQ(tessellationFactor(8, 0), 8);
    EXPECT_EQ(tessellationFactor(8, 3), 1);
}

TEST(EdgeTessellation, CoarsensWithDistanceAndNeverSimplifiesBehindTheCamera)
{
    const Camera c = lookingNorth();
    const EdgeErrors e{{0.5f, 1.0f, 2.0f, 4.0f}};
    int last = -1;
    for (double y : {20.0, 100.0, 400.0, 1600.0, 6400.0}) {
        const int d = edgeSimplification(c.viewProjection(), c.viewport(), {0, y, -100}, e, 4, 2.0);
        EXPECT_GE(d, last) << y;
        last = d;
    }
    EXPECT_EQ(last, 4);
    EXPECT_TRUE(
        std::isinf(projectedVerticalSegment(c.viewProjection(), c.viewport(), {0, -50, 0}, 1.0)));
    EXPECT_EQ(edgeSimplification(c.viewProjection(), c.viewport(), {0, -50, 0}, e, 4, 2.0), 0);
}

TEST(EdgeTessellation, TheConservativeRuleMeetsEpsilonAlongTheWholeEdgeAndThePapersDoesNot)
{
    // Random edges of 8 cells of 30 m ahead of a low camera: the conservative d keeps
    // 2λ_e^(d) + Err(P) (what bounds its transition triangles) below ε at every sample of the
    // edge; the paper's Λ_e^(d), tested at the centre only, does not always.
    const Camera c({0, 0, 50}, {0, 1000, 0}, 70.0, {1280, 720}, 1.0, 1e5);
    const glm::dmat4 vp = c.viewProjection();
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    int paper_misses = 0;
    for (int k = 0; k < 2000; ++k) {
        const glm::dvec3 a(-600 + 1200 * u(rng), 30 + 2000 * u(rng), -50 + 30 * u(rng));
        const glm::dvec3 along = u(rng) < 0.5 ? glm::dvec3(240, 0, 0) : glm::dvec3(0, 240, 0);
        const glm::dvec3 b = a + along + glm::dvec3(0, 0, 30 * (u(rng) - 0.5));
        const glm::dvec3 centre = 0.5 * (a + b) + glm::dvec3(0, 0, 10 * (u(rng) - 0.5));
        const EdgeErrors e{{0.5f, 1.5f, 4.0f, 9.0f}, 0.4f}; // Λ^(d) = λ^(d) + 0.4
        for (const TessellationRule rule :
             {TessellationRule::Conservative, TessellationRule::Paper}) {
            const bool paper = rule == TessellationRule::Paper;
            const int d = edgeSimplification(vp, c.viewport(), a, centre, b, e, 4, 2.0, rule);
            if (d == 0)
                continue;
            const double bound =
                paper ? e.lambda[d - 1] : 2.0 * e.lambda[d - 1] - double(e.patch_error);
            bool within = true;
            for (int i = 0; i <= 8; ++i) {
                const glm::dvec3 p =
                    i <= 4 ? a + (centre - a) * (i / 4.0) : centre + (b - centre) * ((i - 4) / 4.0);
                within &= projectedVerticalSegment(vp, c.viewport(), p, bound) < 2.0;
            }
            // ... and no finer than that needs: one level coarser already misses it.
            if (!paper && d < 4) {
                const double coarser = 2.0 * e.lambda[d] - double(e.patch_error);
                bool all_within = true;
                for (const glm::dvec3& p : {a, centre, b, nearestPointOfSegment(a, b)})
                    all_within &= projectedVerticalSegment(vp, c.viewport(), p, coarser) < 2.0;
                EXPECT_FALSE(all_within) << k;
            }
            if (!paper) {
                EXPECT_TRUE(within) << k;
            } else {
                paper_misses += !within;
            }
        }
    }
    EXPECT_GT(paper_misses, 20);
}

TEST(EdgeTessellation, TheInteriorIsTheMinimumOfTheEdgesForThePaperAndItsOwnTestOtherwise)
{
    const int edges[4] = {8, 2, 4, 1};
    EXPECT_EQ(interiorFactor(TessellationRule::Paper, 8, edges, 0, 0), 1);
    // No edge finer than its own test: that test alone.
    EXPECT_EQ(interiorFactor(TessellationRule::Conservative, 8, {1, 2, 1, 1}, 1, 0), 4);
    // A finer edge: the transition test (2λ + Err(P)) decides, never finer than that edge.
    EXPECT_EQ(interiorFactor(TessellationRule::Conservative, 8, edges, 3, 3), 1);
    EXPECT_EQ(interiorFactor(TessellationRule::Conservative, 8, edges, 3, 1), 4);
    EXPECT_EQ(interiorFactor(TessellationRule::Conservative, 8, edges, 3, 0), 8);
    EXPECT_EQ(interiorFactor(TessellationRule::Conservative, 8, {1, 4, 2, 1}, 3, 0), 4);
    const EdgeErrors t = transitionErrors(EdgeErrors{{0.5f, 1.5f, 4.0f, 9.0f}, 0.25f});
    EXPECT_EQ(t.lambda[0], 0.75f);
    EXPECT_EQ(t.lambda[3], 17.75f);
    // The interior's own test: the most demanding of its corners, centre and the nearest
    // point of its box, never coarser than any of them.
    const Camera c({0, 0, 300}, {0, 1000, 0}, 70.0, {1280, 720}, 1.0, 1e5);
    const glm::dmat4 vp = c.viewProjection();
    const EdgeErrors e{{0.5f, 1.5f, 4.0f, 9.0f}};
    std::mt19937 rng(9);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    int histogram[5] = {};
    for (int k = 0; k < 500; ++k) {
        const glm::dvec3 lo(-600 + 1200 * u(rng), 50 + 3000 * u(rng), -300 - 100 * u(rng));
        const glm::dvec3 hi = lo + glm::dvec3(240, 240, 100 * u(rng));
        const glm::dvec3 corners[4] = {{lo.x, lo.y, lo.z + 10},
                                       {hi.x, lo.y, hi.z},
                                       {lo.x, hi.y, lo.z},
                                       {hi.x, hi.y, hi.z - 5}};
        const glm::dvec3 centre = 0.5 * (lo + hi);
        const int d = interiorSimplification(vp, c.viewport(), corners, centre, lo, hi, e, 4, 2.0);
        int expect =
            edgeSimplification(vp, c.viewport(), glm::clamp(glm::dvec3(0), lo, hi), e, 4, 2.0);
        for (const glm::dvec3& p : {corners[0], corners[1], corners[2], corners[3], centre})
            expect = std::min(expect, edgeSimplification(vp, c.viewport(), p, e, 4, 2.0));
        EXPECT_EQ(d, expect) << k;
        ++histogram[d];
    }
    int levels_seen = 0;
    for (int d = 0; d <= 4; ++d)
        levels_seen += histogram[d] > 5;
    EXPECT_GE(levels_seen, 3) << "the boxes must exercise several d";
}
