// Err_Appr and λ(d) checked by brute force on real terrain (tests/data).
#include "test_support.h"

#include "ridge/io/raster_source.h"
#include "ridge/pyramid/level_pyramid.h"
#include "ridge/pyramid/patch_error.h"
#include "ridge/pyramid/tessellation_block_errors.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <tuple>

using namespace ridge;

namespace {

// Value of a patch's surface at a fractional position (u, v) in patch-sample units:
// bilinear or one of the two triangulations of the cell.
enum class Surface { Bilinear, DiagonalA, DiagonalB };

double surfaceAt(const std::vector<uint16_t>& patch, int n, double u, double v, Surface kind)
{
    const int i = std::min(static_cast<int>(u), n - 2);
    const int j = std::min(static_cast<int>(v), n - 2);
    const double s = u - i, t = v - j;
    const double a = patch[j * n + i], b = patch[j * n + i + 1];
    const double c = patch[(j + 1) * n + i], e = patch[(j + 1) * n + i + 1];
    switch (kind) {
    case Surface::Bilinear:
        return (a * (1 - s) + b * s) * (1 - t) + (c * (1 - s) + e * s) * t;
    case Surface::DiagonalA: // split along (0,0)-(1,1)
        return s >= t ? a + (b - a) * s + (e - b) * t : a + (e - c) * s + (c - a) * t;
    case Surface::DiagonalB: // split along (1,0)-(0,1)
        return s + t <= 1 ? a + (b - a) * s + (c - a) * t
                          : e + (c - e) * (1 - s) + (b - e) * (1 - t);
    }
    return 0;
}

class ErrorBounds : public ::testing::TestWithParam<std::tuple<const char*, PyramidFilter>> {};

} // namespace

// The recursion's Err_Appr must bound |surface(P) - h_finest| at every full-resolution sample
// P covers (inside the valid extent), for the bilinear surface and both triangulations.
TEST_P(ErrorBounds, ErrApprBoundsTheTrueDeviationFromFullResolution)
{
    const auto [file, filter] = GetParam();
    const io::ElevationRaster raster = io::ingestRaster(test::dataPath(file));
    const PyramidGeometry g(raster.grid.width, raster.grid.height, 17); // many levels
    const LevelPyramid pyramid(raster.grid, g, filter);
    const PatchErrors errors = computePatchErrors(pyramid);
    const int n = g.patchSize();
    std::vector<uint16_t> patch(n * n);
    double tightest_ratio = 0.0; // how close the bound comes to the truth somewhere
    for (int64_t index = 0; index < g.patchCount(); ++index) {
        const PatchId p = g.patchAt(index);
        extractPatch(pyramid.level(p.level), n, p, patch.data());
        const int64_t step = g.step(p.level);
        const int64_t x0 = p.x * g.cells() * step, y0 = p.y * g.cells() * step;
        const int64_t x1 = std::min<int64_t>(x0 + g.cells() * step, g.width() - 1);
        const int64_t y1 = std::min<int64_t>(y0 + g.cells() * step, g.height() - 1);
        double worst = 0.0;
        for (int64_t y = y0; y <= y1; ++y)
            for (int64_t x = x0; x <= x1; ++x)
                for (Surface kind : {Surface::Bilinear, Surface::DiagonalA, Surface::DiagonalB}) {
                    const double s =
                        surfaceAt(patch, n, double(x - x0) / step, double(y - y0) / step, kind);
                    worst = std::max(worst, std::fabs(s - raster.grid.at(int(x), int(y))));
                }
        ASSERT_LE(worst, errors.err_appr[index] + 1e-6)
            << "patch level " << p.level << " x " << p.x << " y " << p.y;
        if (errors.err_appr[index] > 0)
            tightest_ratio = std::max(tightest_ratio, worst / errors.err_appr[index]);
        // min/max cover the patch's own samples and every full-resolution sample it covers.
        for (uint16_t v : patch) {
            ASSERT_GE(v, errors.min_code[index]);
            ASSERT_LE(v, errors.max_code[index]);
        }
        for (int64_t y = y0; y <= y1; ++y)
            for (int64_t x = x0; x <= x1; ++x) {
                ASSERT_GE(raster.grid.at(int(x), int(y)), errors.min_code[index]);
                ASSERT_LE(raster.grid.at(int(x), int(y)), errors.max_code[index]);
            }
    }
    // A bound that is never approached would be useless for LOD selection.
    EXPECT_GT(tightest_ratio, 0.5);
}

INSTANTIATE_TEST_SUITE_P(
    RealTerrain, ErrorBounds,
    ::testing::Combine(::testing::Values("everest_crop.tif", "rainier_voids.tif"),
                       ::testing::Values(PyramidFilter::Decimate, PyramidFilter::Neville4)));

TEST(PatchErrors, FinestLevelHasZeroApproximationError)
{
    const io::ElevationRaster raster = io::ingestRaster(test::dataPath("everest_crop.tif"));
    const PyramidGeometry g(raster.grid.width, raster.grid.height, 33);
    const LevelPyramid pyramid(raster.grid, g, PyramidFilter::Decimate);
    const PatchErrors errors = computePatchErrors(pyramid);
    for (int64_t i = g.firstPatchIndex(g.finestLevel()); i < g.patchCount(); ++i)
        EXPECT_EQ(errors.err_appr[i], 0.f);
    EXPECT_GT(errors.err_appr[0], 100.f); // Everest: the root patch is far from exact
}

TEST(PatchQuadtree, NeighbouringPatchesShareTheirBordersExactlyAtEveryLevel)
{
    const io::ElevationRaster raster = io::ingestRaster(test::dataPath("everest_crop.tif"));
    for (PyramidFilter filter : {PyramidFilter::Decimate, PyramidFilter::Neville4}) {
        const PyramidGeometry g(raster.grid.width, raster.grid.height, 33);
        const LevelPyramid pyramid(raster.grid, g, filter);
        const int n = g.patchSize();
        std::vector<uint16_t> a(n * n), b(n * n);
        for (int l = 0; l < g.levelCount(); ++l)
            for (int y = 0; y < g.patchesY(l); ++y)
                for (int x = 0; x < g.patchesX(l); ++x) {
                    extractPatch(pyramid.level(l), n, {l, x, y}, a.data());
                    if (x + 1 < g.patchesX(l)) {
                        extractPatch(pyramid.level(l), n, {l, x + 1, y}, b.data());
                        for (int t = 0; t < n; ++t)
                            ASSERT_EQ(a[t * n + n - 1], b[t * n]);
                    }
                    if (y + 1 < g.patchesY(l)) {
                        extractPatch(pyramid.level(l), n, {l, x, y + 1}, b.data());
                        for (int t = 0; t < n; ++t)
                            ASSERT_EQ(a[(n - 1) * n + t], b[t]);
                    }
                }
    }
}

TEST(LevelPyramid, DecimatedLevelsAreSubsamplesOfTheFinerLevel)
{
    const io::ElevationRaster raster = io::ingestRaster(test::dataPath("everest_crop.tif"));
    const PyramidGeometry g(raster.grid.width, raster.grid.height, 65);
    const LevelPyramid pyramid(raster.grid, g, PyramidFilter::Decimate);
    for (int l = 0; l + 1 < g.levelCount(); ++l)
        for (int j = 0; j < g.levelHeight(l); ++j)
            for (int i = 0; i < g.levelWidth(l); ++i)
                ASSERT_EQ(pyramid.level(l).at(i, j), pyramid.level(l + 1).at(2 * i, 2 * j));
}

TEST(LevelPyramid, NevilleFilterKeepsConstantsAndSmoothsASpike)
{
    CodeGrid flat{9, 9, std::vector<uint16_t>(81, 1000)};
    const CodeGrid c = coarsenNeville4(flat);
    EXPECT_EQ(c.width, 5);
    for (uint16_t v : c.codes)
        EXPECT_EQ(v, 1000);
    flat.at(4, 4) = 1640; // one spike of +640 lands on an even sample
    const CodeGrid s = coarsenNeville4(flat);
    EXPECT_EQ(s.at(2, 2), 1000 + std::lround(640 * (46.0 / 64) * (46.0 / 64)));
}

// λ(d) by brute force: every skipped sample against every triangle of the simplified
// triangulation that contains it (point-in-triangle with barycentric coordinates), for both
// diagonals, plus the bilinear interpolant.
TEST(TessellationBlockErrors, MatchBruteForceOnRealTerrain)
{
    const io::ElevationRaster raster = io::ingestRaster(test::dataPath("everest_crop.tif"));
    const TessellationBlockLayout layout{33, 8};
    const PyramidGeometry g(raster.grid.width, raster.grid.height, 33);
    const LevelPyramid pyramid(raster.grid, g, PyramidFilter::Decimate);
    const int n = 33;
    std::vector<uint16_t> patch(n * n);
    std::vector<float> lambda(layout.valuesPerPatch());
    ASSERT_EQ(layout.levels(), 3);
    const int l = g.finestLevel();
    for (int py = 0; py < g.patchesY(l); ++py) {
        for (int px = 0; px < g.patchesX(l); ++px) {
            extractPatch(pyramid.level(l), n, {l, px, py}, patch.data());
            computeTessellationBlockErrors(patch.data(), layout, lambda.data());
            auto h = [&](int x, int y) { return double(patch[y * n + x]); };
            for (int r = 0; r < 4; ++r)
                for (int s = 0; s < 4; ++s)
                    for (int d = 1; d <= 3; ++d) {
                        const int st = 1 << d;
                        double brute = 0;
                        for (int y = r * 8; y <= r * 8 + 8; ++y)
                            for (int x = s * 8; x <= s * 8 + 8; ++x) {
                                // Every simplified cell whose closed square contains (x, y).
                                for (int cy = r * 8; cy < r * 8 + 8; cy += st)
                                    for (int cx = s * 8; cx < s * 8 + 8; cx += st) {
                                        if (x < cx || x > cx + st || y < cy || y > cy + st)
                                            continue;
                                        const double P[4][3] = {
                                            {double(cx), double(cy), h(cx, cy)},
                                            {double(cx + st), double(cy), h(cx + st, cy)},
                                            {double(cx), double(cy + st), h(cx, cy + st)},
                                            {double(cx + st), double(cy + st),
                                             h(cx + st, cy + st)}};
                                        const int tris[4][3] = {
                                            {0, 1, 3}, {0, 3, 2}, {0, 1, 2}, {1, 3, 2}};
                                        for (const auto& tri : tris) {
                                            const double* A = P[tri[0]];
                                            const double* B = P[tri[1]];
                                            const double* C = P[tri[2]];
                                            const double det = (B[0] - A[0]) * (C[1] - A[1]) -
                                                               (C[0] - A[0]) * (B[1] - A[1]);
                                            const double wb = ((x - A[0]) * (C[1] - A[1]) -
                                                               (C[0] - A[0]) * (y - A[1])) /
                                                              det;
                                            const double wc = ((B[0] - A[0]) * (y - A[1]) -
                                                               (x - A[0]) * (B[1] - A[1])) /
                                                              det;
                                            const double wa = 1 - wb - wc;
                                            if (wa < -1e-12 || wb < -1e-12 || wc < -1e-12)
                                                continue;
                                            brute = std::max(
                                                brute, std::fabs(h(x, y) - (wa * A[2] + wb * B[2] +
                                                                            wc * C[2])));
                                        }
                                        const double u = double(x - cx) / st,
                                                     v = double(y - cy) / st;
                                        const double bil =
                                            (P[0][2] * (1 - u) + P[1][2] * u) * (1 - v) +
                                            (P[2][2] * (1 - u) + P[3][2] * u) * v;
                                        brute = std::max(brute, std::fabs(h(x, y) - bil));
                                    }
                            }
                        ASSERT_NEAR(lambda[(r * 4 + s) * 3 + d - 1], brute, 1e-3)
                            << "patch " << px << "," << py << " block " << r << "," << s << " d "
                            << d;
                    }
        }
    }
}

TEST(TessellationBlockErrors, LayoutStoresUpToFourLevels)
{
    EXPECT_EQ((TessellationBlockLayout{129, 8}.levels()), 3);
    EXPECT_EQ((TessellationBlockLayout{129, 16}.levels()), 4);
    EXPECT_EQ((TessellationBlockLayout{129, 64}.levels()), 4);
    EXPECT_FALSE((TessellationBlockLayout{129, 6}.valid()));
    EXPECT_FALSE((TessellationBlockLayout{17, 32}.valid()));
}
