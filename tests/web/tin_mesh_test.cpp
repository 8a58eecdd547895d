#include "ridge/web/tin_mesh.h"

#include "fractal_terrain.h"

#include "ridge/core/error.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <numeric>
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

// Twice the signed area of abc in the documented frame (x, −y), y growing south like the
// row (coordinates up to 2^24: the products fit int64).
int64_t doubleArea(int64_t ax, int64_t ay, int64_t bx, int64_t by, int64_t cx, int64_t cy)
{
    return (bx - ax) * (-(cy - ay)) - (-(by - ay)) * (cx - ax);
}

// 0, 1, ..., count − 1: the uniform grid's line positions.
std::vector<int32_t> unitLines(int count)
{
    std::vector<int32_t> out(static_cast<size_t>(count));
    std::iota(out.begin(), out.end(), 0);
    return out;
}

// Evaluates the mesh at every sample independently of the library, in the grid's real
// coordinates (column c at x = xs[c], row r at y = ys[r]): each triangle's bounding box of
// samples is searched for the samples inside it (closed, by the signs of exact integer
// sub-areas), which get the triangle's barycentric interpolation. Returns, per sample, the
// worst |sample − mesh| over the triangles containing it, or −1 when none does.
std::vector<double> sampleErrors(const Tin& tin, const std::vector<float>& heights,
                                 const std::vector<int32_t>& xs, const std::vector<int32_t>& ys)
{
    const size_t width = xs.size();
    std::vector<double> worst(heights.size(), -1.0);
    for (size_t t = 0; t < tin.triangles.size(); t += 3) {
        int64_t c[3], r[3], x[3], y[3];
        double h[3];
        for (int k = 0; k < 3; ++k) {
            const uint32_t v = tin.triangles[t + k];
            c[k] = tin.columns[v], r[k] = tin.rows[v], h[k] = tin.heights[v];
            x[k] = xs[size_t(c[k])], y[k] = ys[size_t(r[k])];
        }
        const int64_t area = doubleArea(x[0], y[0], x[1], y[1], x[2], y[2]);
        for (int64_t row = *std::min_element(r, r + 3); row <= *std::max_element(r, r + 3); ++row)
            for (int64_t column = *std::min_element(c, c + 3);
                 column <= *std::max_element(c, c + 3); ++column) {
                const int64_t sx = xs[size_t(column)], sy = ys[size_t(row)];
                const int64_t a0 = doubleArea(x[1], y[1], x[2], y[2], sx, sy);
                const int64_t a1 = doubleArea(x[2], y[2], x[0], y[0], sx, sy);
                const int64_t a2 = doubleArea(x[0], y[0], x[1], y[1], sx, sy);
                if (a0 < 0 || a1 < 0 || a2 < 0)
                    continue;
                const double mesh =
                    (double(a0) * h[0] + double(a1) * h[1] + double(a2) * h[2]) / double(area);
                const size_t sample = size_t(row) * width + size_t(column);
                double& w = worst[sample];
                w = std::max(w, std::abs(double(heights[sample]) - mesh));
            }
    }
    return worst;
}

std::vector<double> sampleErrors(const Tin& tin, const Grid& g)
{
    return sampleErrors(tin, g.heights, unitLines(g.width), unitLines(g.height));
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

// A rectilinear grid: column c at x = xs[c], row r at y = ys[r], heights row-major.
struct Rectilinear {
    std::vector<int32_t> xs, ys;
    std::vector<float> heights;

    int width() const { return int(xs.size()); }
    int height() const { return int(ys.size()); }
    float at(int column, int row) const { return heights[size_t(row) * xs.size() + column]; }
};

// `count` line positions from `origin`: the first gap `first`, the last `last`, the ones
// between `interior` (a tile cut from an archive: the tile's edges fall between the
// archive's samples, which are `interior` apart). Two lines: one gap, `first`.
std::vector<int32_t> tileLines(int count, int32_t origin, int32_t first, int32_t interior,
                               int32_t last)
{
    std::vector<int32_t> out{origin};
    for (int i = 1; i < count; ++i)
        out.push_back(out.back() + (i == 1 ? first : i == count - 1 ? last : interior));
    return out;
}

// `count` line positions from `origin` with gaps drawn uniformly from [1, max_gap].
std::vector<int32_t> randomLines(int count, int32_t origin, int32_t max_gap, uint32_t seed)
{
    std::mt19937 rng(seed);
    std::vector<int32_t> out{origin};
    for (int i = 1; i < count; ++i)
        out.push_back(out.back() + 1 + int32_t(rng() % uint32_t(max_gap)));
    return out;
}

// Rough terrain (fractalGrid's heights) on the given lines.
Rectilinear fractalRectilinear(std::vector<int32_t> xs, std::vector<int32_t> ys, uint32_t seed)
{
    const Grid g = fractalGrid(int(xs.size()), int(ys.size()), seed);
    return {std::move(xs), std::move(ys), g.heights};
}

Tin build(const Rectilinear& g, double max_error)
{
    return buildTin(g.heights, g.xs, g.ys, max_error);
}

// The rectilinear grids the tests below run on: tiles cut from archives (edge gaps unlike
// the interior one, smaller and larger), degenerate sizes, anisotropic and random spacing,
// and positions at the top of the range (2^24).
std::vector<Rectilinear> rectilinearGrids()
{
    const int32_t top = int32_t(1) << 24;
    std::vector<Rectilinear> grids;
    // Unit spacing: the uniform form's grid (TheUniformFormIsTheRectilinearOneWithUnitSpacing).
    grids.push_back(fractalRectilinear(tileLines(65, 0, 1, 1, 1), tileLines(33, 0, 1, 1, 1), 100));
    grids.push_back(fractalRectilinear(tileLines(65, 0, 700, 1000, 300),
                                       tileLines(33, 0, 450, 1000, 550), 101));
    grids.push_back(fractalRectilinear(tileLines(33, 5, 1, 3, 2), tileLines(65, 0, 2, 3, 1), 102));
    grids.push_back(
        fractalRectilinear(tileLines(129, 1000, 17, 30, 9), tileLines(129, 2000, 29, 30, 3), 103));
    grids.push_back(fractalRectilinear(tileLines(2, 0, 7, 7, 7), tileLines(2, 10, 3, 3, 3), 104));
    grids.push_back(fractalRectilinear(tileLines(17, 0, 3, 10, 9), tileLines(2, 0, 5, 5, 5), 105));
    grids.push_back(fractalRectilinear(tileLines(2, 0, 1, 1, 1), tileLines(40, 0, 1, 4, 3), 106));
    grids.push_back(
        fractalRectilinear(tileLines(3, 0, 1, 1, 900), tileLines(3, 0, 900, 1, 1), 107));
    grids.push_back(fractalRectilinear(tileLines(60, 0, 50, 100, 20), tileLines(40, 0, 7, 10, 3),
                                       108)); // 10:1 anisotropic
    grids.push_back(
        fractalRectilinear(randomLines(100, 0, 5000, 109), randomLines(37, 0, 5000, 110), 111));
    // Positions spanning [0, 2^24], where the predicates' bit budget is tightest.
    grids.push_back(fractalRectilinear(tileLines(65, 0, 100, 262144, top - 100 - 62 * 262144),
                                       tileLines(33, 0, 1, 524288, top - 1 - 30 * 524288), 112));
    EXPECT_EQ(grids.back().xs.back(), top);
    EXPECT_EQ(grids.back().ys.back(), top);
    return grids;
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

TEST(TinMesh, EverySampleLiesWithinTheBoundOnRectilinearGrids)
{
    for (const Rectilinear& g : rectilinearGrids()) {
        for (const double bound : {0.0, 0.5, 2.0, 10.0}) {
            const Tin tin = build(g, bound);
            const std::vector<double> errors = sampleErrors(tin, g.heights, g.xs, g.ys);
            double worst = 0.0;
            for (size_t s = 0; s < errors.size(); ++s) {
                ASSERT_GE(errors[s], 0.0) << "sample " << s << " lies in no triangle";
                worst = std::max(worst, errors[s]);
            }
            const std::string grid = std::to_string(g.width()) + "x" + std::to_string(g.height()) +
                                     " from x " + std::to_string(g.xs[0]) + " at " +
                                     std::to_string(bound);
            EXPECT_LE(worst, bound + kSlack) << grid;
            EXPECT_LE(tin.max_error, bound) << grid << ": the reported error keeps the bound";
            EXPECT_NEAR(tin.max_error, worst, kSlack) << grid << ": and is the true error";
        }
    }
}

TEST(TinMesh, RectilinearTrianglesTileTheRectangleCounterClockwiseInRealCoordinates)
{
    for (const Rectilinear& g : rectilinearGrids()) {
        for (const double bound : {0.0, 1.0, 5.0, 50.0}) {
            const Tin tin = build(g, bound);
            const size_t vertices = tin.columns.size();
            ASSERT_EQ(tin.rows.size(), vertices);
            ASSERT_EQ(tin.heights.size(), vertices);
            ASSERT_EQ(tin.triangles.size() % 3, 0u);
            std::set<std::pair<uint32_t, uint32_t>> cells;
            for (size_t v = 0; v < vertices; ++v) {
                ASSERT_LT(tin.columns[v], uint32_t(g.width())) << "columns are grid indices";
                ASSERT_LT(tin.rows[v], uint32_t(g.height())) << "rows are grid indices";
                EXPECT_TRUE(cells.insert({tin.columns[v], tin.rows[v]}).second);
                EXPECT_EQ(tin.heights[v], g.at(int(tin.columns[v]), int(tin.rows[v])));
            }
            const uint32_t e = uint32_t(g.width() - 1), s = uint32_t(g.height() - 1);
            ASSERT_GE(vertices, 4u);
            EXPECT_EQ(std::pair(tin.columns[0], tin.rows[0]), std::pair(0u, 0u));
            EXPECT_EQ(std::pair(tin.columns[1], tin.rows[1]), std::pair(0u, s));
            EXPECT_EQ(std::pair(tin.columns[2], tin.rows[2]), std::pair(e, s));
            EXPECT_EQ(std::pair(tin.columns[3], tin.rows[3]), std::pair(e, 0u));

            auto x = [&](uint32_t v) { return int64_t(g.xs[tin.columns[v]]); };
            auto y = [&](uint32_t v) { return int64_t(g.ys[tin.rows[v]]); };
            int64_t area = 0;
            std::map<std::pair<uint32_t, uint32_t>, int> directed;
            for (size_t t = 0; t < tin.triangles.size(); t += 3) {
                const uint32_t a = tin.triangles[t], b = tin.triangles[t + 1],
                               c = tin.triangles[t + 2];
                ASSERT_LT(std::max({a, b, c}), uint32_t(vertices));
                const int64_t doubled = doubleArea(x(a), y(a), x(b), y(b), x(c), y(c));
                EXPECT_GT(doubled, 0) << "triangle " << t / 3 << " at " << bound;
                area += doubled;
                for (const auto& edge : {std::pair{a, b}, {b, c}, {c, a}})
                    ++directed[edge];
            }
            const int64_t width = g.xs.back() - g.xs.front(), height = g.ys.back() - g.ys.front();
            EXPECT_EQ(area, 2 * width * height) << "the triangles cover the rectangle's area";
            for (const auto& [edge, count] : directed) {
                EXPECT_EQ(count, 1);
                if (directed.count({edge.second, edge.first}))
                    continue;
                const uint32_t c0 = tin.columns[edge.first], c1 = tin.columns[edge.second];
                const uint32_t r0 = tin.rows[edge.first], r1 = tin.rows[edge.second];
                EXPECT_TRUE((c0 == c1 && (c0 == 0 || c0 == e)) ||
                            (r0 == r1 && (r0 == 0 || r0 == s)))
                    << "an unshared edge lies inside the rectangle";
            }
        }
    }
}

// Delaunay in the real coordinates, not the indices: on these grids (edge gaps unlike the
// interior, 10:1 anisotropy, random gaps) the two differ.
TEST(TinMesh, RectilinearInteriorEdgesAreLocallyDelaunayInRealCoordinates)
{
    __extension__ typedef __int128 Int128;
    for (const Rectilinear& g : rectilinearGrids()) {
        for (const double bound : {0.0, 0.5, 3.0}) {
            const Tin tin = build(g, bound);
            std::map<std::pair<uint32_t, uint32_t>, uint32_t> opposite;
            for (size_t t = 0; t < tin.triangles.size(); t += 3)
                for (int k = 0; k < 3; ++k)
                    opposite[{tin.triangles[t + k], tin.triangles[t + (k + 1) % 3]}] =
                        tin.triangles[t + (k + 2) % 3];
            for (const auto& [edge, p] : opposite) {
                const auto across = opposite.find({edge.second, edge.first});
                if (across == opposite.end())
                    continue;
                // In (x, −y) relative to the far vertex q: differences up to 2^24, squared
                // lengths and minors up to 2^49, the determinant below 2^100.
                const uint32_t q = across->second;
                int64_t dx[3], dy[3];
                const uint32_t abc[3] = {edge.first, edge.second, p};
                for (int k = 0; k < 3; ++k) {
                    dx[k] = int64_t(g.xs[tin.columns[abc[k]]]) - g.xs[tin.columns[q]];
                    dy[k] = -(int64_t(g.ys[tin.rows[abc[k]]]) - g.ys[tin.rows[q]]);
                }
                auto lift = [&](int k) { return Int128(dx[k] * dx[k] + dy[k] * dy[k]); };
                const Int128 det = lift(0) * (dx[1] * dy[2] - dy[1] * dx[2]) +
                                   lift(1) * (dx[2] * dy[0] - dy[2] * dx[0]) +
                                   lift(2) * (dx[0] * dy[1] - dy[0] * dx[1]);
                EXPECT_LE(det, 0) << g.width() << "x" << g.height() << " edge " << edge.first << "-"
                                  << edge.second << " at " << bound;
            }
        }
    }
}

TEST(TinMesh, TheUniformFormIsTheRectilinearOneWithUnitSpacing)
{
    const std::tuple<int, int, uint32_t> shapes[] = {{65, 33, 1}, {2, 2, 4},    {17, 2, 5},
                                                     {2, 40, 6},  {100, 37, 7}, {129, 129, 3}};
    for (const auto& [width, height, seed] : shapes) {
        const Grid g = fractalGrid(width, height, seed);
        for (const double bound : {0.0, 0.5, 2.0, 10.0}) {
            const Tin uniform = build(g, bound);
            const Tin rectilinear = buildTin(g.heights, unitLines(width), unitLines(height), bound);
            EXPECT_EQ(uniform.columns, rectilinear.columns) << width << "x" << height;
            EXPECT_EQ(uniform.rows, rectilinear.rows);
            EXPECT_EQ(uniform.heights, rectilinear.heights);
            EXPECT_EQ(uniform.triangles, rectilinear.triangles);
            EXPECT_EQ(uniform.max_error, rectilinear.max_error);
        }
    }
}

TEST(TinMesh, APlaneInRealCoordinatesNeedsOnlyTheFourCornersOnAnyRectilinearGrid)
{
    // Heights 1000 + x/256 − y/512: exact in float, and small enough here (positions below
    // 2^17) that every product the library forms is exact, so the plane is met exactly.
    const std::pair<std::vector<int32_t>, std::vector<int32_t>> grids[] = {
        {tileLines(65, 0, 700, 1000, 300), tileLines(33, 0, 450, 1000, 550)},
        {tileLines(2, 0, 1000, 1000, 1000), tileLines(2, 0, 300, 300, 300)},
        {tileLines(3, 0, 10, 1, 500), tileLines(100, 0, 1, 7, 300)},
        {randomLines(40, 0, 1000, 121), randomLines(30, 0, 1000, 122)},
    };
    for (const auto& [xs, ys] : grids) {
        Rectilinear plane{xs, ys, {}};
        for (const int32_t y : ys)
            for (const int32_t x : xs)
                plane.heights.push_back(float(1000.0 + x / 256.0 - y / 512.0));
        const Tin tin = build(plane, 0.0);
        EXPECT_EQ(tin.columns.size(), 4u) << xs.size() << "x" << ys.size();
        EXPECT_EQ(tin.triangles.size(), 6u);
        EXPECT_EQ(tin.max_error, 0.0);
        if (xs.size() > 2 && ys.size() > 2) {
            // Read as a uniform grid (by index), the same heights are no plane.
            EXPECT_GT(buildTin(plane.heights, plane.width(), plane.height(), 0.0).columns.size(),
                      4u);
        }
    }
}

TEST(TinMesh, RectilinearBorderVerticesDependOnlyOnTheirBorderSamplesAndPositions)
{
    const std::vector<int32_t> ys = tileLines(49, 0, 450, 1000, 550);
    const Rectilinear a = fractalRectilinear(tileLines(65, 0, 700, 1000, 300), ys, 131);
    // Other x positions (interior and edges) and other heights, but a's east column.
    Rectilinear b = fractalRectilinear(randomLines(40, 20, 3000, 132), ys, 133);
    for (int r = 0; r < b.height(); ++r)
        b.heights[size_t(r) * b.xs.size() + b.xs.size() - 1] = a.at(a.width() - 1, r);
    // a's east column again, on other row positions.
    Rectilinear c = a;
    c.ys = tileLines(49, 0, 1000, 1000, 1000);
    bool positions_matter = false;
    for (const double bound : {0.0, 0.5, 2.0, 10.0}) {
        const Tin ta = build(a, bound), tb = build(b, bound), tc = build(c, bound);
        const BorderVertices east = columnVertices(ta, uint32_t(a.width() - 1));
        EXPECT_EQ(east, columnVertices(tb, uint32_t(b.width() - 1))) << bound;
        EXPECT_NE(columnVertices(ta, 0), columnVertices(tb, 0)) << "the other borders differ";
        positions_matter = positions_matter || east != columnVertices(tc, uint32_t(c.width() - 1));
    }
    EXPECT_TRUE(positions_matter) << "the same samples at other positions choose otherwise";
}

TEST(TinMesh, NeighbouringRectilinearTilesShareTheirBorderVertices)
{
    // Two tiles of one rectilinear grid sharing its column 64: the west tile's east border
    // and the east tile's west border are the same samples at the same positions.
    const Rectilinear g = fractalRectilinear(tileLines(129, 0, 700, 1000, 300),
                                             tileLines(65, 0, 450, 1000, 550), 141);
    auto cut = [&](int c0) {
        Rectilinear out{{g.xs.begin() + c0, g.xs.begin() + c0 + 65}, g.ys, {}};
        for (int r = 0; r < g.height(); ++r)
            for (int c = c0; c < c0 + 65; ++c)
                out.heights.push_back(g.at(c, r));
        return out;
    };
    const Rectilinear west = cut(0), east = cut(64);
    for (const double bound : {0.0, 1.0, 4.0, 30.0}) {
        const BorderVertices shared = columnVertices(build(west, bound), 64);
        EXPECT_EQ(shared, columnVertices(build(east, bound), 0)) << bound;
        EXPECT_GE(shared.size(), 2u);
    }
}

TEST(TinMesh, HostileRectilinearGridsThrowNamingTheParameter)
{
    const int32_t top = int32_t(1) << 24;
    auto message = [&](const std::vector<int32_t>& xs, const std::vector<int32_t>& ys,
                       std::vector<float> heights, double bound = 1.0) {
        try {
            buildTin(heights, xs, ys, bound);
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string("no throw");
    };
    auto zeros = [](size_t n) { return std::vector<float>(n, 0.0f); };
    const std::vector<int32_t> ok = {0, 5, 10};
    auto contains = [](const std::string& text, const std::string& part) {
        return text.find(part) != std::string::npos;
    };
    EXPECT_TRUE(contains(message({0, 1, 1}, ok, zeros(9)), "xs[2] is 1")) << "equal";
    EXPECT_TRUE(contains(message(ok, {0, 9, 4}, zeros(9)), "ys[2] is 4")) << "decreasing";
    EXPECT_TRUE(contains(message({-1, 5, 10}, ok, zeros(9)), "xs[0] is -1")) << "negative";
    EXPECT_TRUE(contains(message(ok, {0, 5, top + 1}, zeros(9)), "ys[2] is 16777217"));
    EXPECT_TRUE(contains(message({0, 5, top}, {0, top - 1, top}, zeros(9)), "no throw"))
        << "2^24 itself is in range";
    EXPECT_TRUE(contains(message({7}, ok, zeros(3)), "xs.size()")) << "one column";
    EXPECT_TRUE(contains(message(ok, {}, zeros(0)), "ys.size()")) << "no row";
    EXPECT_TRUE(contains(message(unitLines(65537), {0, 1}, zeros(2 * 65537)), "xs.size()"));
    EXPECT_TRUE(contains(message(ok, ok, zeros(8)), "heights has 8")) << "size mismatch: fewer";
    EXPECT_TRUE(contains(message(ok, {0, 1}, zeros(9)), "heights has 9")) << "size mismatch: more";
    std::vector<float> bad = zeros(9);
    bad[5] = std::numeric_limits<float>::quiet_NaN();
    EXPECT_TRUE(contains(message(ok, ok, bad), "heights at row 1, column 2"));
    EXPECT_TRUE(contains(message(ok, ok, zeros(9), -1.0), "max_error"));
    EXPECT_TRUE(
        contains(message(ok, ok, zeros(9), std::numeric_limits<double>::infinity()), "max_error"));
}
