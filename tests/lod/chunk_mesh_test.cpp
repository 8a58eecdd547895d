#include "ridge/lod/chunk_mesh.h"

#include "ridge/core/error.h"

#include "fractal_terrain.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <random>

using namespace ridge;
using namespace ridge::lod;

namespace {

// Rough terrain (diamond-square, tests/support/fractal_terrain.h) in codes.
std::vector<uint16_t> fractalPatch(int n, uint32_t seed, double roughness)
{
    const std::vector<double> h =
        ridge::test::diamondSquare(n, seed, 2000.0, 500.0, roughness * (n - 1), 0.55);
    std::vector<uint16_t> codes(h.size());
    for (size_t i = 0; i < h.size(); ++i)
        codes[i] = uint16_t(std::clamp(std::lround(h[i]), 0L, 65535L));
    return codes;
}

struct Xy {
    int x, y;
};
Xy xyOf(uint32_t v, int n)
{
    return {int(v % uint32_t(n)), int(v / uint32_t(n))};
}
int64_t cross(Xy o, Xy a, Xy b)
{
    return int64_t(a.x - o.x) * (b.y - o.y) - int64_t(a.y - o.y) * (b.x - o.x);
}

// Worst |sample − mesh| over all samples, and how many samples no triangle covers.
std::pair<double, int> measure(const ChunkMesh& m, const std::vector<uint16_t>& codes, int n)
{
    std::vector<double> worst(codes.size(), -1.0);
    for (uint32_t t = 0; t < m.surface_indices; t += 3) {
        const Xy p0 = xyOf(m.indices[t], n), p1 = xyOf(m.indices[t + 1], n),
                 p2 = xyOf(m.indices[t + 2], n);
        const double area2 = double(cross(p0, p1, p2));
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                const Xy p{x, y};
                const int64_t w0 = cross(p1, p2, p), w1 = cross(p2, p0, p), w2 = cross(p0, p1, p);
                if (w0 < 0 || w1 < 0 || w2 < 0)
                    continue;
                auto h = [&](Xy q) { return double(codes[size_t(q.y) * n + q.x]); };
                const double plane = (w0 * h(p0) + w1 * h(p1) + w2 * h(p2)) / area2;
                double& w = worst[size_t(y) * n + x];
                w = std::max(w, std::abs(h(p) - plane));
            }
    }
    double max_dev = 0.0;
    int uncovered = 0;
    for (const double w : worst) {
        uncovered += w < 0.0;
        max_dev = std::max(max_dev, w);
    }
    return {max_dev, uncovered};
}

} // namespace

TEST(ChunkMesh, EverySampleIsWithinTheToleranceOfTheMesh)
{
    for (const int n : {17, 33, 65})
        for (const uint32_t seed : {1u, 2u, 3u})
            for (const double tolerance : {0.0, 0.5, 2.0, 8.0, 40.0}) {
                const std::vector<uint16_t> codes = fractalPatch(n, seed, 1.5);
                const ChunkMesh m = buildChunkMesh(codes.data(), n, tolerance);
                const auto [worst, uncovered] = measure(m, codes, n);
                EXPECT_EQ(uncovered, 0) << n << " " << seed << " " << tolerance;
                EXPECT_LE(worst, tolerance + 1e-9) << n << " " << seed << " " << tolerance;
                EXPECT_NEAR(m.max_deviation, worst, 1e-9) << "the mesh reports its own error";
            }
}

TEST(ChunkMesh, IsAConformingCounterClockwiseTriangulationClosedByItsSkirt)
{
    const int n = 65, c = n - 1;
    const std::vector<uint16_t> codes = fractalPatch(n, 7, 2.0);
    for (const double tolerance : {0.0, 3.0, 25.0}) {
        const ChunkMesh m = buildChunkMesh(codes.data(), n, tolerance);
        ASSERT_EQ(m.indices.size() % 3, 0u);
        ASSERT_EQ(m.surface_indices % 3, 0u);
        int64_t area2 = 0;
        std::map<std::pair<uint32_t, uint32_t>, int> surface_edges, all_edges;
        for (size_t t = 0; t < m.indices.size(); t += 3)
            for (int e = 0; e < 3; ++e) {
                uint32_t a = m.indices[t + e], b = m.indices[t + (e + 1) % 3];
                if (b < a)
                    std::swap(a, b);
                ++all_edges[{a, b}];
                if (t < m.surface_indices)
                    ++surface_edges[{a, b}];
            }
        for (uint32_t t = 0; t < m.surface_indices; t += 3) {
            const int64_t a =
                cross(xyOf(m.indices[t], n), xyOf(m.indices[t + 1], n), xyOf(m.indices[t + 2], n));
            EXPECT_GT(a, 0) << "counter-clockwise, like the full-grid mesh";
            area2 += a;
        }
        EXPECT_EQ(area2, 2 * int64_t(c) * c) << "the triangles tile the patch";
        // An edge used once lies on the patch border; a T-junction would leave one inside.
        for (const auto& [edge, count] : surface_edges) {
            const Xy a = xyOf(edge.first, n), b = xyOf(edge.second, n);
            const bool border =
                (a.x == b.x && (a.x == 0 || a.x == c)) || (a.y == b.y && (a.y == 0 || a.y == c));
            EXPECT_EQ(count, border ? 1 : 2) << tolerance;
        }
        // With the skirt, only the feet's bottom edges stay open.
        const uint32_t feet = uint32_t(n) * uint32_t(n);
        for (const auto& [edge, count] : all_edges) {
            const bool bottom = edge.first >= feet && edge.second >= feet;
            EXPECT_EQ(count, bottom ? 1 : 2) << tolerance;
        }
    }
}

TEST(ChunkMesh, SimplifiesAsFarAsTheToleranceLets)
{
    const int n = 33;
    // A plane: two triangles even at tolerance 0.
    std::vector<uint16_t> plane(size_t(n) * n);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
            plane[size_t(y) * n + x] = uint16_t(100 + 3 * x + 2 * y);
    EXPECT_EQ(buildChunkMesh(plane.data(), n, 0.0).surface_indices, 6u);

    const std::vector<uint16_t> rough = fractalPatch(n, 11, 1.5);
    const auto [lo, hi] = std::minmax_element(rough.begin(), rough.end());
    EXPECT_EQ(buildChunkMesh(rough.data(), n, double(*hi - *lo)).surface_indices, 6u);
    uint32_t previous = UINT32_MAX;
    for (const double tolerance : {0.0, 1.0, 4.0, 16.0, 64.0}) {
        const uint32_t count = buildChunkMesh(rough.data(), n, tolerance).surface_indices;
        EXPECT_LE(count, previous) << tolerance;
        previous = count;
    }
    EXPECT_LT(buildChunkMesh(rough.data(), n, 4.0).surface_indices,
              buildChunkMesh(rough.data(), n, 0.0).surface_indices / 2);
}

// On a globe a flat triangle sags below the curved surface by more the larger it is: with a
// sag, no triangle stays larger than the tolerance lets (a plane of heights no longer makes
// two triangles), the mesh still conforms (it tiles the patch with no T-junction), and no
// sag gives the plane's mesh back.
TEST(ChunkMesh, OnAGlobeNoTriangleSagsPastTheTolerance)
{
    const int n = 33, c = n - 1;
    std::vector<uint16_t> plane(size_t(n) * n);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
            plane[size_t(y) * n + x] = uint16_t(100 + 3 * x + 2 * y);
    const ChunkSag sag = [](int cells) { return 0.5 * cells * cells; }; // ∝ chord², codes
    EXPECT_EQ(buildChunkMesh(plane.data(), n, 0.0, c, c, {}).surface_indices, 6u);
    for (const double tolerance : {0.0, 2.0, 8.0, 32.0, 2000.0}) {
        const ChunkMesh m = buildChunkMesh(plane.data(), n, tolerance, c, c, sag);
        int64_t area2 = 0;
        std::map<std::pair<uint32_t, uint32_t>, int> edges;
        for (uint32_t t = 0; t < m.surface_indices; t += 3) {
            const Xy p[3] = {xyOf(m.indices[t], n), xyOf(m.indices[t + 1], n),
                             xyOf(m.indices[t + 2], n)};
            area2 += cross(p[0], p[1], p[2]);
            const int extent =
                std::max(std::max({p[0].x, p[1].x, p[2].x}) - std::min({p[0].x, p[1].x, p[2].x}),
                         std::max({p[0].y, p[1].y, p[2].y}) - std::min({p[0].y, p[1].y, p[2].y}));
            // A half cell (extent 1) cannot split further; anything larger sags within τ.
            EXPECT_TRUE(extent == 1 || sag(extent) <= tolerance)
                << "extent " << extent << " at τ " << tolerance;
            for (int e = 0; e < 3; ++e) {
                uint32_t a = m.indices[t + e], b = m.indices[t + (e + 1) % 3];
                if (b < a)
                    std::swap(a, b);
                ++edges[{a, b}];
            }
        }
        EXPECT_EQ(area2, 2 * int64_t(c) * c) << "the triangles tile the patch";
        for (const auto& [edge, count] : edges) {
            const Xy a = xyOf(edge.first, n), b = xyOf(edge.second, n);
            const bool border =
                (a.x == b.x && (a.x == 0 || a.x == c)) || (a.y == b.y && (a.y == 0 || a.y == c));
            EXPECT_EQ(count, border ? 1 : 2) << "no T-junction at τ " << tolerance;
        }
        if (tolerance >= sag(c))
            EXPECT_EQ(m.surface_indices, 6u);
        else
            EXPECT_GT(m.surface_indices, 6u);
    }
}

TEST(ChunkMesh, NoTriangleCrossesTheValidExtentAndOnlyValidSamplesCount)
{
    // A patch past the terrain's east or south border: samples beyond (vx, vy) are padding.
    const int n = 65, c = n - 1;
    const std::vector<uint16_t> codes = fractalPatch(n, 5, 1.5);
    for (const auto& [vx, vy] : {std::pair{37, 64}, {64, 11}, {20, 45}, {1, 1}}) {
        std::vector<uint16_t> padded = codes;
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x)
                if (x > vx || y > vy)
                    padded[size_t(y) * n + x] = uint16_t((x * 7919 + y * 104729) % 4000);
        const double tolerance = 6.0;
        const ChunkMesh m = buildChunkMesh(padded.data(), n, tolerance, vx, vy);
        double valid_worst = 0.0;
        auto h = [&](Xy q) { return double(padded[size_t(q.y) * n + q.x]); };
        for (uint32_t t = 0; t < m.surface_indices; t += 3) {
            const Xy p0 = xyOf(m.indices[t], n), p1 = xyOf(m.indices[t + 1], n),
                     p2 = xyOf(m.indices[t + 2], n);
            const int x0 = std::min({p0.x, p1.x, p2.x}), x1 = std::max({p0.x, p1.x, p2.x});
            const int y0 = std::min({p0.y, p1.y, p2.y}), y1 = std::max({p0.y, p1.y, p2.y});
            EXPECT_FALSE(x0 < vx && vx < x1) << vx << "," << vy;
            EXPECT_FALSE(y0 < vy && vy < y1) << vx << "," << vy;
            const double area2 = double(cross(p0, p1, p2));
            for (int y = 0; y <= vy; ++y)
                for (int x = 0; x <= vx; ++x) {
                    const Xy q{x, y};
                    const int64_t w0 = cross(p1, p2, q), w1 = cross(p2, p0, q),
                                  w2 = cross(p0, p1, q);
                    if (w0 >= 0 && w1 >= 0 && w2 >= 0)
                        valid_worst = std::max(
                            valid_worst,
                            std::abs(h(q) - (w0 * h(p0) + w1 * h(p1) + w2 * h(p2)) / area2));
                }
        }
        EXPECT_LE(valid_worst, tolerance + 1e-9) << vx << "," << vy;
        EXPECT_NEAR(m.max_deviation, valid_worst, 1e-9) << vx << "," << vy;
        const auto [worst, uncovered] = measure(m, padded, n);
        EXPECT_EQ(uncovered, 0);
        EXPECT_GT(worst, tolerance) << "the padding is not fitted";
    }
    EXPECT_THROW(buildChunkMesh(codes.data(), n, 1.0, c + 1, c), Error);
}

TEST(ChunkMesh, RejectsPatchSizesThatAreNotAPowerOfTwoPlusOne)
{
    const std::vector<uint16_t> codes(100, 0);
    EXPECT_THROW(buildChunkMesh(codes.data(), 10, 1.0), Error);
    EXPECT_THROW(buildChunkMesh(codes.data(), 1, 1.0), Error);
    EXPECT_THROW(buildChunkMesh(codes.data(), 9, -1.0), Error);
}
