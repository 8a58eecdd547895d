#include "ridge/lod/geomorph.h"

#include "error_expectations.h"
#include "ridge/core/error.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <vector>

using namespace ridge;
using namespace ridge::lod;
using ridge::test::expectError;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::vector<uint16_t> randomCodes(int n, uint32_t seed, int lo = 0, int hi = 65535)
{
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> code(lo, hi);
    std::vector<uint16_t> codes(size_t(n) * n);
    for (uint16_t& c : codes)
        c = uint16_t(code(rng));
    return codes;
}

// The drawn surface of an n×n grid `h` at continuous sample coordinates (x, y) ∈ [0, n−1]²:
// cell (i, j) split along b–c into (a, b, c) and (b, d, c), linear on each triangle. With
// dyadic x, y and integer or half-integer h every operation is exact in double.
template <typename T> double surfaceAt(const T* h, int n, double x, double y)
{
    const int i = std::min(int(std::floor(x)), n - 2), j = std::min(int(std::floor(y)), n - 2);
    const double fx = x - i, fy = y - j;
    auto at = [&](int di, int dj) { return double(h[size_t(j + dj) * n + size_t(i + di)]); };
    const double a = at(0, 0), b = at(1, 0), c = at(0, 1), d = at(1, 1);
    if (fx + fy <= 1.0)
        return a + fx * (b - a) + fy * (c - a);             // triangle (a, b, c)
    return d + (1.0 - fx) * (c - d) + (1.0 - fy) * (b - d); // triangle (b, d, c)
}

std::vector<double> targetsOf(const std::vector<uint16_t>& parent, int n, int qx, int qy)
{
    std::vector<double> target(size_t(n) * n);
    targetHeights(parent.data(), n, qx, qy, target.data());
    return target;
}

GeomorphFrame testFrame()
{
    return {0.25, -120.0, 30.0, 20.0};
}

} // namespace

// ---- Target heights ---------------------------------------------------------------------

TEST(GeomorphTargets, AFullyMorphedChildIsExactlyItsParentsSurfaceEverywhere)
{
    for (int n : {5, 9, 17, 65}) {
        const std::vector<uint16_t> parent = randomCodes(n, 11u + n);
        const int m = (n - 1) / 2;
        std::mt19937 rng(n);
        // Dyadic points: 1/64 of a child cell, so both evaluations are exact in double.
        std::uniform_int_distribution<int> k(0, 64 * (n - 1));
        for (int qy = 0; qy < 2; ++qy)
            for (int qx = 0; qx < 2; ++qx) {
                const std::vector<double> target = targetsOf(parent, n, qx, qy);
                int mismatches = 0;
                for (int s = 0; s < 20000; ++s) {
                    const double x = k(rng) / 64.0, y = k(rng) / 64.0;
                    const double child = surfaceAt(target.data(), n, x, y);
                    const double drawn =
                        surfaceAt(parent.data(), n, qx * m + x / 2, qy * m + y / 2);
                    if (child != drawn && ++mismatches <= 3)
                        ADD_FAILURE()
                            << "n " << n << " quadrant (" << qx << ", " << qy << ") at (" << x
                            << ", " << y << "): child " << child << ", parent " << drawn;
                }
                EXPECT_EQ(mismatches, 0) << "n " << n << " quadrant (" << qx << ", " << qy << ")";
            }
    }
}

TEST(GeomorphTargets, EvenSamplesAreParentSamplesAndOddOnesMeansOfAnEdgeOrTheBCDiagonal)
{
    const int n = 9, m = 4;
    const std::vector<uint16_t> parent = randomCodes(n, 5);
    auto P = [&](int x, int y) { return double(parent[size_t(y) * n + x]); };
    const std::vector<double> t = targetsOf(parent, n, 1, 0);
    auto T = [&](int i, int j) { return t[size_t(j) * n + i]; };
    EXPECT_EQ(T(0, 0), P(m, 0));
    EXPECT_EQ(T(8, 8), P(2 * m, m));
    EXPECT_EQ(T(1, 0), (P(m, 0) + P(m + 1, 0)) / 2);     // edge along x
    EXPECT_EQ(T(2, 3), (P(m + 1, 1) + P(m + 1, 2)) / 2); // edge along y
    EXPECT_EQ(T(3, 5), (P(m + 2, 2) + P(m + 1, 3)) / 2); // cell centre: b = (x+1, y), c = (x, y+1)
}

TEST(GeomorphTargets, SixteenBitTargetsAreWithinHalfACodeAndRoundTiesUp)
{
    for (int n : {5, 33, 129}) {
        const std::vector<uint16_t> parent = randomCodes(n, 3u * n);
        for (int q = 0; q < 4; ++q) {
            const std::vector<double> exact = targetsOf(parent, n, q & 1, q >> 1);
            std::vector<uint16_t> codes(exact.size());
            targetCodes(parent.data(), n, q & 1, q >> 1, codes.data());
            for (size_t s = 0; s < exact.size(); ++s) {
                ASSERT_LE(std::abs(codes[s] - exact[s]), 0.5) << s;
                if (exact[s] != std::floor(exact[s])) {
                    ASSERT_EQ(codes[s], exact[s] + 0.5) << s;
                }
            }
        }
    }
    // The extremes: no overflow at 65535.
    std::vector<uint16_t> top(25, 65535);
    std::vector<uint16_t> codes(25);
    targetCodes(top.data(), 5, 1, 1, codes.data());
    EXPECT_TRUE(std::all_of(codes.begin(), codes.end(), [](uint16_t c) { return c == 65535; }));
}

TEST(GeomorphTargets, RefuseBadSizesQuadrantsAndNulls)
{
    const std::vector<uint16_t> parent(size_t(4097) * 4097, 0);
    std::vector<double> out(parent.size());
    for (int n : {-1, 0, 1, 2, 3, 4, 6, 8, 10, 4096, 4099, 8193})
        expectError([&] { targetHeights(parent.data(), n, 0, 0, out.data()); }, "must be 2^k + 1");
    expectError([&] { targetHeights(parent.data(), 5, 2, 0, out.data()); }, "qx is 2");
    expectError([&] { targetHeights(parent.data(), 5, 0, -1, out.data()); }, "qy is -1");
    expectError([&] { targetHeights(nullptr, 5, 0, 0, out.data()); }, "parent_codes is null");
    expectError([&] { targetCodes(parent.data(), 5, 0, 0, nullptr); }, "out is null");
    EXPECT_NO_THROW(targetHeights(parent.data(), 4097, 1, 1, out.data()));
}

// ---- Morph factor -----------------------------------------------------------------------

TEST(GeomorphMorphFactor, IsOneWhenTheParentMeetsEpsilonAndZeroWhenTheOwnShapeMissesIt)
{
    EXPECT_EQ(morphFactor(0.1, 0.9, 1.0), 1.0);
    EXPECT_EQ(morphFactor(0.1, 1.0, 1.0), 1.0);
    EXPECT_EQ(morphFactor(1.0, 5.0, 1.0), 0.0);
    EXPECT_EQ(morphFactor(3.0, 5.0, 1.0), 0.0);
    EXPECT_EQ(morphFactor(0.0, 2.0, 1.0), 0.5);
    EXPECT_DOUBLE_EQ(morphFactor(0.5, 3.0, 1.0), 0.2);
    // A parent coarser in error than its child is the norm; the reverse still gives the largest t.
    EXPECT_EQ(morphFactor(2.0, 0.5, 1.0), 1.0);
}

TEST(GeomorphMorphFactor, IsTheLargestTWhoseProjectedBoundHolds)
{
    std::mt19937 rng(42);
    std::uniform_real_distribution<double> err(0.0, 4.0);
    for (int k = 0; k < 100000; ++k) {
        const double eps = 0.05 + err(rng), a = err(rng), b = a + err(rng);
        const double t = morphFactor(a, b, eps);
        ASSERT_GE(t, 0.0);
        ASSERT_LE(t, 1.0);
        if (a <= eps) {
            ASSERT_LE((1 - t) * a + t * b, eps * (1 + 1e-12)) << a << " " << b << " " << eps;
            if (t < 1.0) { // larger t would break the bound: it is tight
                ASSERT_NEAR((1 - t) * a + t * b, eps, 1e-12 * eps);
            }
        } else {
            ASSERT_EQ(t, 0.0);
        }
    }
}

TEST(GeomorphMorphFactor, IsContinuousAtBothSwitchesSoNeitherPops)
{
    const double eps = 1.0;
    // The patch appears as its parent's error rises past ε: t → 1.
    for (double above : {1e-3, 1e-6, 1e-9})
        EXPECT_NEAR(morphFactor(0.3, eps + above, eps), 1.0, 2 * above);
    // It gives way to its children as its own error rises past ε: t → 0, children at 1.
    for (double below : {1e-3, 1e-6, 1e-9}) {
        EXPECT_NEAR(morphFactor(eps - below, 4.0, eps), 0.0, below);
        EXPECT_EQ(morphFactor(0.2, eps - below, eps), 1.0); // each child, its parent at s_own
    }
    // Monotone: t falls as the camera approaches (both errors grow in proportion).
    double previous = 1.0;
    for (double distance = 1000; distance > 1; distance *= 0.97) {
        const double t = morphFactor(300.0 / distance, 900.0 / distance, eps);
        EXPECT_LE(t, previous) << distance;
        previous = t;
    }
}

TEST(GeomorphMorphFactor, ReplacingAPatchByItsChildrenDoesNotMoveTheSurface)
{
    // Parent P, one child C. At the switch s_P = ε: P at t_P = 0 draws its own surface; C at
    // t_C = morphFactor(s_C, s_P = ε) = 1 draws P's surface too, at every point.
    const int n = 17, m = 8;
    const double eps = 2.0, s_P = eps, s_PP = 3 * eps, s_C = eps / 3;
    const std::vector<uint16_t> parent = randomCodes(n, 99);
    const std::vector<uint16_t> child_own = randomCodes(n, 100);
    const std::vector<double> target = targetsOf(parent, n, 0, 1);
    const double t_P = morphFactor(s_P, s_PP, eps), t_C = morphFactor(s_C, s_P, eps);
    EXPECT_EQ(t_P, 0.0);
    EXPECT_EQ(t_C, 1.0);
    std::vector<double> child(target.size());
    for (size_t s = 0; s < child.size(); ++s)
        child[s] = (1 - t_C) * child_own[s] + t_C * target[s];
    for (int y = 0; y <= 64 * (n - 1); y += 7)
        for (int x = 0; x <= 64 * (n - 1); x += 5)
            ASSERT_EQ(surfaceAt(child.data(), n, x / 64.0, y / 64.0),
                      surfaceAt(parent.data(), n, x / 128.0, m + y / 128.0));
}

TEST(GeomorphMorphFactor, RefusesNaNAndNegativesAndHandlesInfinity)
{
    expectError([] { morphFactor(kNaN, 1.0, 1.0); }, "own_screen_error is nan");
    expectError([] { morphFactor(0.5, kNaN, 1.0); }, "parent_screen_error is nan");
    expectError([] { morphFactor(-0.1, 1.0, 1.0); }, "own_screen_error is -0.1");
    expectError([] { morphFactor(0.5, 2.0, kNaN); }, "epsilon is nan");
    expectError([] { morphFactor(0.5, 2.0, kInf); }, "epsilon is inf");
    expectError([] { morphFactor(0.5, 2.0, 0.0); }, "epsilon is 0");
    // screen_space_error() is +inf with the camera inside the box.
    EXPECT_EQ(morphFactor(0.5, kInf, 1.0), 0.0);
    EXPECT_EQ(morphFactor(kInf, kInf, 1.0), 0.0);
    EXPECT_EQ(morphFactor(kInf, 0.5, 1.0), 1.0);
}

TEST(GeomorphMorphFactor, HeightMorphIsMixInFloat)
{
    EXPECT_EQ(morphHeight(10.0f, 20.0f, 0.0f), 10.0f);
    EXPECT_EQ(morphHeight(10.0f, 20.0f, 1.0f), 20.0f);
    EXPECT_EQ(morphHeight(10.0f, 20.0f, 0.25f), 12.5f);
    const float h = 1234.5678f, target = -98.765f, t = 0.3f;
    EXPECT_EQ(morphHeight(h, target, t), h * (1.0f - t) + target * t);
}

// ---- Blocks and indices -----------------------------------------------------------------

TEST(GeomorphBlocks, HoldAtMost128CellsSoInBlockCoordinatesFitAByte)
{
    EXPECT_EQ(geomorphBlockCells(5), 4);
    EXPECT_EQ(geomorphBlocksPerSide(5), 1);
    EXPECT_EQ(geomorphBlockCells(129), 128);
    EXPECT_EQ(geomorphBlocksPerSide(129), 1);
    EXPECT_EQ(geomorphBlockCells(257), 128);
    EXPECT_EQ(geomorphBlocksPerSide(257), 2);
    EXPECT_EQ(geomorphBlocksPerSide(4097), 32);
    EXPECT_EQ(geomorphVertexCount(5), 25u);
    EXPECT_EQ(geomorphVertexCount(257), 4u * 129 * 129);
    expectError([] { geomorphBlockCells(100); }, "patch size n is 100");
    expectError([] { geomorphBlockIndexCount(129); }, "block_cells");
    expectError([] { geomorphBlockIndexCount(0); }, "block_cells");
}

TEST(GeomorphBlocks, IndicesCoverEveryCellOnceAlongTheBCDiagonalCounterClockwise)
{
    for (int b : {1, 4, 128}) {
        std::vector<uint16_t> indices(geomorphBlockIndexCount(b));
        buildGeomorphBlockIndices(b, indices.data());
        const int side = b + 1;
        std::set<uint16_t> used;
        std::map<std::pair<int, int>, int>
            diagonals; // per cell: which diagonal its triangles share
        for (size_t k = 0; k < indices.size(); k += 3) {
            int xs[3], ys[3];
            for (int v = 0; v < 3; ++v) {
                ASSERT_LT(indices[k + v], side * side);
                used.insert(indices[k + v]);
                xs[v] = indices[k + v] % side, ys[v] = indices[k + v] / side;
            }
            const int cross = (xs[1] - xs[0]) * (ys[2] - ys[0]) - (ys[1] - ys[0]) * (xs[2] - xs[0]);
            ASSERT_EQ(cross, 1) << "half a cell, counter-clockwise in (i, j)";
            const int cx = *std::min_element(xs, xs + 3), cy = *std::min_element(ys, ys + 3);
            ASSERT_LE(*std::max_element(xs, xs + 3) - cx, 1);
            ASSERT_LE(*std::max_element(ys, ys + 3) - cy, 1);
            // Both triangles of a cell contain b = (cx+1, cy) and c = (cx, cy+1).
            int has_bc = 0;
            for (int v = 0; v < 3; ++v)
                has_bc += (xs[v] == cx + 1 && ys[v] == cy) || (xs[v] == cx && ys[v] == cy + 1);
            ASSERT_EQ(has_bc, 2);
            ++diagonals[{cx, cy}];
        }
        EXPECT_EQ(diagonals.size(), size_t(b) * b);
        for (const auto& [cell, count] : diagonals)
            ASSERT_EQ(count, 2);
        EXPECT_EQ(used.size(), size_t(side) * side);
    }
}

// ---- Layouts and packing ----------------------------------------------------------------

TEST(GeomorphLayouts, BytesPerVertexAreThePapersLayouts)
{
    using L = GeomorphLayout;
    using S = GeomorphShading;
    EXPECT_EQ(geomorphVertexBytes(L::Standard, S::ColourOnly), 12);
    EXPECT_EQ(geomorphVertexBytes(L::Standard, S::Lit), 24);
    EXPECT_EQ(geomorphVertexBytes(L::FloatMorph, S::ColourOnly), 16);
    EXPECT_EQ(geomorphVertexBytes(L::FloatMorph, S::Lit), 28);
    EXPECT_EQ(geomorphVertexBytes(L::Compact, S::ColourOnly), 6);
    EXPECT_EQ(geomorphVertexBytes(L::Compact, S::Lit), 8);
    for (int n : {129, 257, 4097}) {
        std::printf("n = %4d bytes/sample:", n);
        for (L l : {L::Standard, L::FloatMorph, L::Compact})
            for (S s : {S::ColourOnly, S::Lit}) {
                const double bytes = geomorphBytesPerSample(l, s, n);
                EXPECT_GE(bytes, geomorphVertexBytes(l, s));
                EXPECT_LE(bytes, geomorphVertexBytes(l, s) * 1.04);
                std::printf(" %.3f", bytes);
            }
        std::printf("  (standard, float-morph, compact; colour-only, lit)\n");
    }
}

TEST(GeomorphPacking, LitVerticesAreTheStructsAndColourOnlyTheirPrefix)
{
    const int n = 257;
    const std::vector<uint16_t> parent = randomCodes(n, 1, 1000, 3000);
    const std::vector<uint16_t> own = randomCodes(n, 2, 1000, 1100); // slopes up to ~35°
    const std::vector<double> target = targetsOf(parent, n, 1, 0);
    const GeomorphFrame frame = testFrame();
    std::vector<float> normals(3 * size_t(n) * n);
    patchNormals(own.data(), n, frame, normals.data());
    const GeomorphPatchData patch{n, own.data(), target.data(), normals.data()};
    const size_t count = geomorphVertexCount(n);

    std::vector<StandardVertex> standard(count);
    std::vector<FloatMorphVertex> floats(count);
    std::vector<CompactVertex> compact(count);
    const double t = 0.37;
    packStandard(patch, frame, t, GeomorphShading::Lit, standard.data());
    packFloatMorph(patch, frame, GeomorphShading::Lit, floats.data());
    packCompact(patch, HemisphereMap::Orthographic, GeomorphShading::Lit, compact.data());
    std::vector<CompactBlock> blocks(size_t(geomorphBlocksPerSide(n)) * geomorphBlocksPerSide(n));
    buildCompactBlocks(n, 7, blocks.data());

    const int b = geomorphBlockCells(n), side = b + 1;
    for (size_t k = 0; k < count; ++k) {
        const CompactBlock& block = blocks[k / (size_t(side) * side)];
        const CompactVertex& c = compact[k];
        // The shader's decode: block origin + in-block coordinates.
        const int i = block.origin_i + c.bx, j = block.origin_j + c.by;
        ASSERT_EQ(block.patch, 7);
        ASSERT_EQ(block.block_cells, b);
        ASSERT_EQ(int(k % side), c.bx);
        const size_t s = size_t(j) * n + i;
        ASSERT_EQ(c.height, own[s]);
        ASSERT_LE(std::abs(c.target - target[s]), 0.5);
        ASSERT_EQ(standard[k].x, float(i) * float(frame.cell_x));
        ASSERT_EQ(standard[k].y, -(float(j) * float(frame.cell_y)));
        ASSERT_EQ(floats[k].x, standard[k].x);
        ASSERT_EQ(floats[k].y, standard[k].y);
        ASSERT_EQ(floats[k].z, geomorphMetres(frame, own[s]));
        ASSERT_EQ(floats[k].target_z, geomorphMetres(frame, target[s]));
        // CPU morph = the vertex shader's morph of the float layout, bit for bit.
        ASSERT_EQ(standard[k].z, morphHeight(floats[k].z, floats[k].target_z, float(t)));
        ASSERT_EQ(standard[k].nx, normals[3 * s]);
        ASSERT_EQ(floats[k].nz, normals[3 * s + 2]);
        const glm::vec3 decoded =
            decodeHemisphereNormal(HemisphereMap::Orthographic, c.normal_u, c.normal_v);
        const double dot = decoded.x * normals[3 * s] + decoded.y * normals[3 * s + 1] +
                           decoded.z * normals[3 * s + 2];
        ASSERT_GT(dot, std::cos(1.0 * M_PI / 180)) << "within 1° on rolling terrain";
    }

    // Colour-only: the same vertices cut to their prefix, tightly packed.
    for (GeomorphLayout layout :
         {GeomorphLayout::Standard, GeomorphLayout::FloatMorph, GeomorphLayout::Compact}) {
        const size_t stride = size_t(geomorphVertexBytes(layout, GeomorphShading::ColourOnly));
        const size_t lit = size_t(geomorphVertexBytes(layout, GeomorphShading::Lit));
        std::vector<unsigned char> packed(count * stride);
        const GeomorphPatchData no_normals{n, own.data(), target.data(), nullptr};
        const unsigned char* full = nullptr;
        if (layout == GeomorphLayout::Standard) {
            packStandard(no_normals, frame, t, GeomorphShading::ColourOnly, packed.data());
            full = reinterpret_cast<const unsigned char*>(standard.data());
        } else if (layout == GeomorphLayout::FloatMorph) {
            packFloatMorph(no_normals, frame, GeomorphShading::ColourOnly, packed.data());
            full = reinterpret_cast<const unsigned char*>(floats.data());
        } else {
            packCompact(no_normals, HemisphereMap::Concentric, GeomorphShading::ColourOnly,
                        packed.data());
            full = reinterpret_cast<const unsigned char*>(compact.data());
        }
        for (size_t k = 0; k < count; ++k)
            ASSERT_EQ(std::memcmp(packed.data() + k * stride, full + k * lit, stride), 0) << k;
    }
}

TEST(GeomorphPacking, MorphEndsAreTheOwnAndTheTargetHeights)
{
    const int n = 5;
    const std::vector<uint16_t> parent = randomCodes(n, 21), own = randomCodes(n, 22);
    const std::vector<double> target = targetsOf(parent, n, 0, 0);
    const GeomorphFrame frame = testFrame();
    const GeomorphPatchData patch{n, own.data(), target.data(), nullptr};
    std::vector<StandardVertex> v0(25), v1(25); // colour-only: 12 B each, fits in 24 B slots
    packStandard(patch, frame, 0.0, GeomorphShading::ColourOnly, v0.data());
    packStandard(patch, frame, 1.0, GeomorphShading::ColourOnly, v1.data());
    const float* f0 = &v0[0].x;
    const float* f1 = &v1[0].x;
    for (int s = 0; s < 25; ++s) {
        EXPECT_EQ(f0[3 * s + 2], geomorphMetres(frame, own[s]));
        EXPECT_EQ(f1[3 * s + 2], geomorphMetres(frame, target[s]));
    }
}

TEST(GeomorphPacking, RefusesBadMorphFactorsFramesAndMissingInputs)
{
    const int n = 5;
    const std::vector<uint16_t> own(25, 100);
    std::vector<double> target(25, 100.0);
    const GeomorphPatchData patch{n, own.data(), target.data(), nullptr};
    std::vector<StandardVertex> out(25);
    const GeomorphFrame frame = testFrame();
    for (double t : {kNaN, -0.01, 1.01, kInf})
        expectError([&] { packStandard(patch, frame, t, GeomorphShading::ColourOnly, out.data()); },
                    "t is ");
    expectError([&] { packStandard(patch, frame, 0.5, GeomorphShading::Lit, out.data()); },
                "patch.normals");
    GeomorphFrame bad = frame;
    bad.cell_x = 0;
    expectError([&] { packFloatMorph(patch, bad, GeomorphShading::ColourOnly, out.data()); },
                "frame.cell_x is 0");
    bad = frame;
    bad.scale = kNaN;
    expectError([&] { packFloatMorph(patch, bad, GeomorphShading::ColourOnly, out.data()); },
                "frame.scale is nan");
    target[7] = kNaN;
    expectError(
        [&] {
            packCompact(patch, HemisphereMap::Concentric, GeomorphShading::ColourOnly, out.data());
        },
        "patch.target[7] is nan");
    target[7] = 70000;
    expectError([&] { packFloatMorph(patch, frame, GeomorphShading::ColourOnly, out.data()); },
                "patch.target[7] is 70000");
    GeomorphPatchData wrong = patch;
    wrong.n = 6;
    expectError([&] { packFloatMorph(wrong, frame, GeomorphShading::ColourOnly, out.data()); },
                "patch size n is 6");
}

// ---- Normals ----------------------------------------------------------------------------

TEST(GeomorphNormals, AreExactForAPlaneIncludingTheBorder)
{
    const int n = 9;
    const GeomorphFrame frame = testFrame(); // scale 0.25 m, cells 30 m east, 20 m south
    const int p = 40, q = -24;               // codes per sample along i, j
    std::vector<uint16_t> codes(size_t(n) * n);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i)
            codes[size_t(j) * n + i] = uint16_t(1000 + p * i + q * j);
    std::vector<float> normals(3 * codes.size());
    patchNormals(codes.data(), n, frame, normals.data());
    // z = 0.25·(p·i + q·j), x = 30 i, y = −20 j: dz/dx = 0.25 p/30, dz/dy = −0.25 q/20.
    const double gx = 0.25 * p / 30, gy = -0.25 * q / 20, len = std::sqrt(gx * gx + gy * gy + 1);
    for (size_t s = 0; s < codes.size(); ++s) {
        EXPECT_NEAR(normals[3 * s], -gx / len, 1e-6) << s;
        EXPECT_NEAR(normals[3 * s + 1], -gy / len, 1e-6) << s;
        EXPECT_NEAR(normals[3 * s + 2], 1 / len, 1e-6) << s;
    }
}
