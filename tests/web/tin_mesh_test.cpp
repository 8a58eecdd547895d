#include "ridge/web/tin_mesh.h"

#include "fractal_terrain.h"

#include "ridge/core/error.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <string>
#include <tuple>
#include <vector>

using namespace ridge;
using namespace ridge::web;

namespace {

// Heights, row-major, as buildTin takes them.
struct Grid {
    int width, height;
    std::vector<float> heights;

    float at(int column, int row) const { return heights[size_t(row) * width + column]; }
};

// A width × height grid of rough terrain (metres): diamond-square on the smallest 2^k + 1
// square covering it, cropped, with a fixed seed.
Grid fractalGrid(int width, int height, uint32_t seed, double amplitude = 200.0,
                 double decay = 0.45)
{
    int n = 2;
    while (n + 1 < std::max(width, height))
        n *= 2;
    ++n;
    const std::vector<double> h =
        ridge::test::diamondSquare(n, seed, 1500.0, amplitude, amplitude, decay);
    Grid grid{width, height, {}};
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            grid.heights.push_back(float(h[size_t(y) * size_t(n) + size_t(x)]));
    return grid;
}

Tin build(const Grid& g, double max_error)
{
    return buildTin(g.heights, g.width, g.height, max_error);
}

// Twice the signed area of abc in the documented frame (x, y) = (column, −row).
int64_t doubleArea(int64_t ac, int64_t ar, int64_t bc, int64_t br, int64_t cc, int64_t cr)
{
    return (bc - ac) * (-(cr - ar)) - (-(br - ar)) * (cc - ac);
}

// Evaluates the mesh at every sample independently of the library: each triangle's bounding
// box is searched for the samples inside it (closed), which get the triangle's barycentric
// interpolation. Returns, per sample, the worst |sample − mesh| over the triangles containing
// it, or −1 when none does.
std::vector<double> sampleErrors(const Tin& tin, const Grid& g)
{
    std::vector<double> worst(g.heights.size(), -1.0);
    for (size_t t = 0; t < tin.triangles.size(); t += 3) {
        int64_t c[3], r[3];
        double h[3];
        for (int k = 0; k < 3; ++k) {
            const uint32_t v = tin.triangles[t + k];
            c[k] = tin.columns[v], r[k] = tin.rows[v], h[k] = tin.heights[v];
        }
        const double area = double(doubleArea(c[0], r[0], c[1], r[1], c[2], r[2]));
        for (int64_t y = *std::min_element(r, r + 3); y <= *std::max_element(r, r + 3); ++y)
            for (int64_t x = *std::min_element(c, c + 3); x <= *std::max_element(c, c + 3); ++x) {
                const double l0 = double(doubleArea(c[1], r[1], c[2], r[2], x, y)) / area;
                const double l1 = double(doubleArea(c[2], r[2], c[0], r[0], x, y)) / area;
                const double l2 = double(doubleArea(c[0], r[0], c[1], r[1], x, y)) / area;
                if (l0 < 0 || l1 < 0 || l2 < 0)
                    continue;
                const double mesh = l0 * h[0] + l1 * h[1] + l2 * h[2];
                double& w = worst[size_t(y) * g.width + x];
                w = std::max(w, std::abs(double(g.at(int(x), int(y))) - mesh));
            }
    }
    return worst;
}

// Rounding slack between the test's barycentric evaluation and the library's (metres).
constexpr double kSlack = 1e-6;

// The (position along the line, height) of the vertices on one border line.
using BorderVertices = std::set<std::pair<uint32_t, float>>;
// The vertices on column `index` (by_column) or row `index`, by their position along it.
BorderVertices lineVertices(const Tin& tin, uint32_t index, bool by_column)
{
    BorderVertices out;
    for (size_t v = 0; v < tin.columns.size(); ++v)
        if ((by_column ? tin.columns[v] : tin.rows[v]) == index)
            out.insert({by_column ? tin.rows[v] : tin.columns[v], tin.heights[v]});
    return out;
}
BorderVertices columnVertices(const Tin& tin, uint32_t column)
{
    return lineVertices(tin, column, true);
}
BorderVertices rowVertices(const Tin& tin, uint32_t row)
{
    return lineVertices(tin, row, false);
}

// The sub-grid of g at columns [c0, c0 + width), rows [r0, r0 + height).
Grid crop(const Grid& g, int c0, int r0, int width, int height)
{
    Grid out{width, height, {}};
    for (int r = r0; r < r0 + height; ++r)
        for (int c = c0; c < c0 + width; ++c)
            out.heights.push_back(g.at(c, r));
    return out;
}

} // namespace

TEST(TinMesh, EverySampleLiesWithinTheBound)
{
    const std::tuple<int, int, uint32_t> shapes[] = {
        {65, 33, 1}, {33, 65, 2},  {129, 129, 3}, {2, 2, 4},   {17, 2, 5},
        {2, 40, 6},  {100, 37, 7}, {600, 3, 8},   {3, 500, 9}, {1500, 2, 10}};
    for (const auto& [width, height, seed] : shapes) {
        const Grid g = fractalGrid(width, height, seed);
        for (const double bound : {0.0, 0.5, 2.0, 10.0}) {
            const Tin tin = build(g, bound);
            const std::vector<double> errors = sampleErrors(tin, g);
            double worst = 0.0;
            for (size_t s = 0; s < errors.size(); ++s) {
                ASSERT_GE(errors[s], 0.0) << "sample " << s << " lies in no triangle";
                worst = std::max(worst, errors[s]);
            }
            EXPECT_LE(worst, bound + kSlack) << width << "x" << height << " at " << bound;
            EXPECT_LE(tin.max_error, bound) << "the reported error keeps the bound exactly";
            EXPECT_NEAR(tin.max_error, worst, kSlack) << "and is the mesh's true error";
        }
    }
}

TEST(TinMesh, TrianglesTileTheRectangleCounterClockwiseWithNorthUp)
{
    for (const double bound : {0.0, 1.0, 5.0, 50.0}) {
        const Grid g = fractalGrid(65, 33, 11);
        const Tin tin = build(g, bound);
        const size_t vertices = tin.columns.size();
        ASSERT_EQ(tin.rows.size(), vertices);
        ASSERT_EQ(tin.heights.size(), vertices);
        ASSERT_EQ(tin.triangles.size() % 3, 0u);

        std::set<std::pair<uint32_t, uint32_t>> positions;
        for (size_t v = 0; v < vertices; ++v) {
            ASSERT_LT(tin.columns[v], uint32_t(g.width));
            ASSERT_LT(tin.rows[v], uint32_t(g.height));
            EXPECT_TRUE(positions.insert({tin.columns[v], tin.rows[v]}).second)
                << "vertex " << v << " repeats a sample";
            EXPECT_EQ(tin.heights[v], g.at(int(tin.columns[v]), int(tin.rows[v])));
        }
        // The corners come first: north-west, south-west, south-east, north-east.
        const uint32_t e = uint32_t(g.width - 1), s = uint32_t(g.height - 1);
        ASSERT_GE(vertices, 4u);
        EXPECT_EQ(std::pair(tin.columns[0], tin.rows[0]), std::pair(0u, 0u));
        EXPECT_EQ(std::pair(tin.columns[1], tin.rows[1]), std::pair(0u, s));
        EXPECT_EQ(std::pair(tin.columns[2], tin.rows[2]), std::pair(e, s));
        EXPECT_EQ(std::pair(tin.columns[3], tin.rows[3]), std::pair(e, 0u));

        int64_t area = 0;
        std::map<std::pair<uint32_t, uint32_t>, int> directed;
        for (size_t t = 0; t < tin.triangles.size(); t += 3) {
            const uint32_t a = tin.triangles[t], b = tin.triangles[t + 1], c = tin.triangles[t + 2];
            ASSERT_LT(std::max({a, b, c}), uint32_t(vertices));
            const int64_t doubled = doubleArea(tin.columns[a], tin.rows[a], tin.columns[b],
                                               tin.rows[b], tin.columns[c], tin.rows[c]);
            EXPECT_GT(doubled, 0) << "triangle " << t / 3 << " at " << bound;
            area += doubled;
            for (const auto& edge : {std::pair{a, b}, {b, c}, {c, a}})
                ++directed[edge];
        }
        EXPECT_EQ(area, 2 * int64_t(e) * s) << "the triangles cover the rectangle's area";
        // Each edge is used once each way, or once on the rectangle's border: with positive
        // areas summing to the rectangle's, the triangles tile it with no gap, overlap or
        // T-junction.
        for (const auto& [edge, count] : directed) {
            EXPECT_EQ(count, 1);
            if (directed.count({edge.second, edge.first}))
                continue;
            const uint32_t c0 = tin.columns[edge.first], c1 = tin.columns[edge.second];
            const uint32_t r0 = tin.rows[edge.first], r1 = tin.rows[edge.second];
            EXPECT_TRUE((c0 == c1 && (c0 == 0 || c0 == e)) || (r0 == r1 && (r0 == 0 || r0 == s)))
                << "an unshared edge lies inside the rectangle";
        }
    }
}

// Lawson's flips leave every interior edge locally Delaunay: the far vertex of the triangle
// across it is not strictly inside the circumcircle of the triangle on this side.
TEST(TinMesh, EveryInteriorEdgeIsLocallyDelaunay)
{
    for (const double bound : {0.0, 0.5, 3.0}) {
        const Grid g = fractalGrid(65, 33, 13);
        const Tin tin = build(g, bound);
        // Directed edge → the vertex opposite it in its triangle.
        std::map<std::pair<uint32_t, uint32_t>, uint32_t> opposite;
        for (size_t t = 0; t < tin.triangles.size(); t += 3)
            for (int k = 0; k < 3; ++k)
                opposite[{tin.triangles[t + k], tin.triangles[t + (k + 1) % 3]}] =
                    tin.triangles[t + (k + 2) % 3];
        int interior_edges = 0;
        for (const auto& [edge, p] : opposite) {
            const auto across = opposite.find({edge.second, edge.first});
            if (across == opposite.end())
                continue;
            ++interior_edges;
            // In (x, y) = (column, −row), relative to the far vertex q; the grid is small, so
            // int64 holds the determinant exactly.
            const uint32_t q = across->second;
            int64_t dx[3], dy[3];
            const uint32_t abc[3] = {edge.first, edge.second, p};
            for (int k = 0; k < 3; ++k) {
                dx[k] = int64_t(tin.columns[abc[k]]) - tin.columns[q];
                dy[k] = -(int64_t(tin.rows[abc[k]]) - tin.rows[q]);
            }
            auto lift = [&](int k) { return dx[k] * dx[k] + dy[k] * dy[k]; };
            const int64_t det = lift(0) * (dx[1] * dy[2] - dy[1] * dx[2]) +
                                lift(1) * (dx[2] * dy[0] - dy[2] * dx[0]) +
                                lift(2) * (dx[0] * dy[1] - dy[0] * dx[1]);
            EXPECT_LE(det, 0) << "edge " << edge.first << "-" << edge.second << " at " << bound;
        }
        EXPECT_GT(interior_edges, 0);
    }
}

TEST(TinMesh, APlaneNeedsOnlyTheFourCornersAndTwoTriangles)
{
    for (const auto& [width, height] : {std::pair{65, 33}, {2, 2}, {257, 257}, {3, 100}}) {
        Grid plane{width, height, {}};
        for (int r = 0; r < height; ++r)
            for (int c = 0; c < width; ++c)
                plane.heights.push_back(float(1000 + 3 * c - 2 * r)); // exact in float
        const Tin tin = build(plane, 0.0);
        EXPECT_EQ(tin.columns.size(), 4u) << width << "x" << height;
        EXPECT_EQ(tin.triangles.size(), 6u) << width << "x" << height;
        EXPECT_EQ(tin.max_error, 0.0);
    }
}

TEST(TinMesh, ZeroBoundOnRoughDataKeepsEverySample)
{
    const Grid g = fractalGrid(65, 33, 21);
    const Tin tin = build(g, 0.0);
    EXPECT_EQ(tin.max_error, 0.0);
    // For this data no sample lies exactly on the plane of three others, so all are kept (on
    // larger grids of float heights a rare one does, and may be left out at bound 0).
    EXPECT_EQ(tin.columns.size(), g.heights.size());
    for (const double error : sampleErrors(tin, g))
        EXPECT_LE(error, kSlack);
}

TEST(TinMesh, BorderVerticesDependOnlyOnTheirBorderSamples)
{
    const int width = 65, height = 49;
    const Grid a = fractalGrid(width, height, 31);
    Grid b = fractalGrid(width, height, 32);
    // b keeps a's east column and south row, nothing else.
    for (int r = 0; r < height; ++r)
        b.heights[size_t(r) * width + width - 1] = a.at(width - 1, r);
    for (int c = 0; c < width; ++c)
        b.heights[size_t(height - 1) * width + c] = a.at(c, height - 1);
    for (const double bound : {0.0, 0.5, 2.0, 10.0}) {
        const Tin ta = build(a, bound), tb = build(b, bound);
        EXPECT_EQ(columnVertices(ta, width - 1), columnVertices(tb, width - 1)) << bound;
        EXPECT_EQ(rowVertices(ta, height - 1), rowVertices(tb, height - 1)) << bound;
        EXPECT_NE(columnVertices(ta, 0), columnVertices(tb, 0)) << "the other borders differ";
    }
}

TEST(TinMesh, NeighbouringTilesShareTheirBorderVertices)
{
    // Four 65×65 tiles cut from one 129×129 grid, sharing their middle column and row.
    const Grid g = fractalGrid(129, 129, 41);
    const Grid nw = crop(g, 0, 0, 65, 65), ne = crop(g, 64, 0, 65, 65);
    const Grid sw = crop(g, 0, 64, 65, 65);
    for (const double bound : {0.0, 1.0, 4.0, 30.0}) {
        const Tin tnw = build(nw, bound), tne = build(ne, bound), tsw = build(sw, bound);
        const BorderVertices east = columnVertices(tnw, 64), west = columnVertices(tne, 0);
        EXPECT_EQ(east, west) << bound;
        EXPECT_GE(east.size(), 2u);
        EXPECT_EQ(rowVertices(tnw, 64), rowVertices(tsw, 0)) << bound;
    }
}

TEST(TinMesh, LargerBoundsNeedFewerVertices)
{
    const Grid g = fractalGrid(257, 257, 51);
    size_t previous = std::numeric_limits<size_t>::max();
    for (const double bound : {0.0, 0.25, 0.5, 1.0, 2.0, 5.0, 10.0, 50.0, 1e4}) {
        const size_t vertices = build(g, bound).columns.size();
        EXPECT_LE(vertices, previous) << bound;
        if (bound == 2.0) {
            EXPECT_LT(vertices, g.heights.size() / 10) << "far fewer than the grid's";
        }
        previous = vertices;
    }
    EXPECT_EQ(previous, 4u) << "a bound above the relief leaves the corners";
}

TEST(TinMesh, SameInputGivesIdenticalOutput)
{
    const Grid g = fractalGrid(100, 77, 61);
    for (const double bound : {0.0, 1.5}) {
        const Tin first = build(g, bound), second = build(g, bound);
        EXPECT_EQ(first.columns, second.columns);
        EXPECT_EQ(first.rows, second.rows);
        EXPECT_EQ(first.heights, second.heights);
        EXPECT_EQ(first.triangles, second.triangles);
        EXPECT_EQ(first.max_error, second.max_error);
    }
}

TEST(TinMesh, HostileInputsThrowNamingTheParameter)
{
    const Grid g = fractalGrid(9, 5, 71);
    auto message = [&](std::vector<float> heights, int width, int height, double bound) {
        try {
            buildTin(heights, width, height, bound);
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string("no throw");
    };
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    EXPECT_NE(message(std::vector<float>(5, 0.0f), 1, 5, 1.0).find("width"), std::string::npos);
    EXPECT_NE(message(std::vector<float>(9, 0.0f), 9, 1, 1.0).find("height"), std::string::npos);
    EXPECT_NE(message(std::vector<float>(65537 * 2, 0.0f), 65537, 2, 1.0).find("width"),
              std::string::npos);
    EXPECT_NE(message(g.heights, 9, 4, 1.0).find("heights"), std::string::npos);
    EXPECT_NE(message(g.heights, 5, 9, 2.0).find("no throw"), std::string::npos)
        << "the same count in another shape is fine";
    std::vector<float> bad = g.heights;
    bad[13] = std::numeric_limits<float>::quiet_NaN();
    EXPECT_NE(message(bad, 9, 5, 1.0).find("heights at row 1, column 4"), std::string::npos);
    bad[13] = -std::numeric_limits<float>::infinity();
    EXPECT_NE(message(bad, 9, 5, 1.0).find("heights"), std::string::npos);
    for (const double bound : {-0.5, nan, inf, -inf})
        EXPECT_NE(message(g.heights, 9, 5, bound).find("max_error"), std::string::npos) << bound;
    EXPECT_NO_THROW(buildTin(g.heights, 9, 5, 0.0));
}
