// Geometry clipmaps' window policy and footprints (lod/clipmap.h, lod/clipmap_footprints.h),
// without GL: the settings refused by name, the nesting rule, the viewer's distance to every
// window's centre (which the transition regions rely on), the L-shaped update strips against a
// brute-force set difference, and the footprints: every cell of a window covered exactly once,
// and the nested levels' triangles watertight (every edge shared by exactly two triangles, the
// coarsest window's outer border once), perimeter triangles included.
#include "ridge/lod/clipmap.h"
#include "ridge/lod/clipmap_footprints.h"

#include "ridge/core/error.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <set>
#include <tuple>

using namespace ridge;
using namespace ridge::lod;

namespace {

TEST(ClipmapSettings, RefusesNotOfTheForm2kMinus1AndLevelsOutOfRangeByName)
{
    for (const int n : {63, 127, 255, 511, 1023}) {
        ClipmapSettings s;
        s.n = n;
        EXPECT_NO_THROW(s.validate()) << n;
        EXPECT_EQ(s.m() * 4 - 1, n);
    }
    for (const int n : {0, 31, 64, 100, 256, 2047, -1}) {
        ClipmapSettings s;
        s.n = n;
        try {
            s.validate();
            ADD_FAILURE() << n << " accepted";
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find("n " + std::to_string(n)), std::string::npos)
                << e.what();
        }
    }
    for (const int levels : {-1, ClipmapSettings::kMaxLevels + 1}) {
        ClipmapSettings s;
        s.levels = levels;
        EXPECT_THROW(s.validate(), Error);
    }
}

TEST(ClipmapSettings, DefaultLevelsLetTheCoarsestWindowSpanTheTerrainFromAnywhereOnIt)
{
    const PyramidGeometry g(2049, 1537, 65);
    for (const int n : {63, 127, 255, 1023}) {
        ClipmapSettings s;
        s.n = n;
        ClipmapWindows w(g, s);
        const int L = w.levelCount();
        ASSERT_GE(L, 1);
        EXPECT_EQ(w.level(L - 1).pyramid_level, g.finestLevel());
        EXPECT_EQ(w.level(L - 1).step, 1);
        // From each corner, the coarsest window holds the opposite one.
        for (const auto& [cx, cy] : {std::pair{0.0, 0.0}, {2048.0, 1536.0}, {0.0, 1536.0}}) {
            w.place(cx, cy);
            const ClipmapLevel& c = w.level(0);
            const int64_t far_x = c.origin_x + (n - 1) * c.step,
                          far_y = c.origin_y + (n - 1) * c.step;
            EXPECT_LE(c.origin_x, 0) << n;
            EXPECT_LE(c.origin_y, 0) << n;
            EXPECT_GE(far_x, 2048) << n;
            EXPECT_GE(far_y, 1536) << n;
        }
        // And the coarsest reads the root (always resident); beyond the archive's levels only
        // as many as the span needs.
        EXPECT_LE(w.level(0).pyramid_level, 0) << n;
        if (w.level(0).pyramid_level < 0) {
            const int64_t reach = (n - 1) / 2 - 2;
            EXPECT_LT(reach * w.level(1).step, 2048) << n;
        }
    }
}

TEST(ClipmapWindows, NestEachLevelInTheCoarserHoleAndStayWithinACellAndAHalfOfTheViewer)
{
    const PyramidGeometry g(4097, 4097, 129);
    for (const int n : {63, 255}) {
        ClipmapSettings s;
        s.n = n;
        ClipmapWindows w(g, s);
        const int64_t m = s.m(), half = (n - 1) / 2;
        std::mt19937 rng(11);
        std::uniform_real_distribution<double> u(-100.0, 4200.0);
        for (int trial = 0; trial < 500; ++trial) {
            const double cx = u(rng), cy = u(rng);
            w.place(cx, cy);
            for (int k = 0; k < w.levelCount(); ++k) {
                const ClipmapLevel& l = w.level(k);
                EXPECT_EQ(l.origin_x % (2 * l.step), 0);
                EXPECT_EQ(l.origin_y % (2 * l.step), 0);
                // The viewer in cells from the window's centre: the transition regions'
                // margin (transitionAlpha) assumes at most 1.5.
                const double dx =
                    std::abs(cx - double(l.origin_x + half * l.step)) / double(l.step);
                const double dy =
                    std::abs(cy - double(l.origin_y + half * l.step)) / double(l.step);
                EXPECT_LE(std::max(dx, dy), 1.5) << "level " << k << " n " << n;
                if (k + 1 < w.levelCount()) {
                    const ClipmapLevel& f = w.level(k + 1);
                    EXPECT_EQ(f.origin_x - l.origin_x, ((m - 1) + l.finer_x) * l.step);
                    EXPECT_EQ(f.origin_y - l.origin_y, ((m - 1) + l.finer_y) * l.step);
                    EXPECT_TRUE(l.finer_x == 0 || l.finer_x == 1);
                    EXPECT_TRUE(l.finer_y == 0 || l.finer_y == 1);
                }
            }
        }
    }
}

TEST(ClipmapWindows, TransitionRegionsAreOneOnThePerimeterAndZeroOnTheInnerBorder)
{
    for (const int n : {63, 127, 255, 511, 1023}) {
        const int m = (n + 1) / 4, half = (n - 1) / 2;
        // The perimeter is at least half − 1.5 cells from the viewer; the inner border at
        // most m + 1.5.
        EXPECT_EQ(transitionAlpha(n, half - 1.5), 1.0) << n;
        EXPECT_EQ(transitionAlpha(n, m + 1.5), 0.0) << n;
        EXPECT_GT(transitionAlpha(n, half - 1.5 - transitionWidth(n)), 0.0) << n;
        EXPECT_LT(transitionAlpha(n, half - 2.5), 1.0) << n;
    }
}

TEST(ClipmapWindows, ShiftsWriteExactlyTheNewSamplesAsAnLShapedStrip)
{
    const PyramidGeometry g(2049, 2049, 65);
    ClipmapSettings s;
    s.n = 63;
    ClipmapWindows w(g, s);
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> step(-40.0, 40.0);
    double cx = 1000.0, cy = 900.0;
    EXPECT_EQ(w.place(cx, cy), w.levelCount()); // the first placement fills every level
    for (int k = 0; k < w.levelCount(); ++k) {
        ASSERT_EQ(w.updateRegions(k).size(), 1u);
        EXPECT_EQ(w.updateRegions(k)[0].area(), int64_t(s.n) * s.n);
    }
    int shifts = 0;
    for (int move = 0; move < 300; ++move) {
        std::vector<LevelRect> before;
        for (int k = 0; k < w.levelCount(); ++k)
            before.push_back(w.level(k).window(s.n));
        const double jump = move % 50 == 49 ? 20.0 : 1.0; // now and then a jump past n
        cx += step(rng) * jump;
        cy += step(rng) * jump;
        shifts += w.place(cx, cy);
        for (int k = 0; k < w.levelCount(); ++k) {
            const LevelRect now = w.level(k).window(s.n);
            std::set<std::pair<int64_t, int64_t>> expected, written;
            for (int64_t y = now.y0; y < now.y1; ++y)
                for (int64_t x = now.x0; x < now.x1; ++x)
                    if (x < before[k].x0 || x >= before[k].x1 || y < before[k].y0 ||
                        y >= before[k].y1)
                        expected.insert({x, y});
            size_t area = 0;
            for (const LevelRect& r : w.updateRegions(k)) {
                area += size_t(r.area());
                for (int64_t y = r.y0; y < r.y1; ++y)
                    for (int64_t x = r.x0; x < r.x1; ++x)
                        written.insert({x, y});
            }
            EXPECT_EQ(written, expected) << "move " << move << " level " << k;
            EXPECT_EQ(area, written.size()) << "the strip's rectangles overlap";
            EXPECT_LE(w.updateRegions(k).size(), 2u);
        }
    }
    EXPECT_GT(shifts, 300);
    // Standing still shifts nothing.
    EXPECT_EQ(w.place(cx, cy), 0);
}

TEST(ClipmapWindows, RefusesACentreThatIsNotFinite)
{
    const PyramidGeometry g(513, 513, 65);
    ClipmapWindows w(g, ClipmapSettings{});
    EXPECT_THROW(w.place(std::nan(""), 0.0), Error);
    EXPECT_THROW(w.place(0.0, 1e300), Error);
    EXPECT_FALSE(w.placed());
}

TEST(ClipmapLevelDeactivation, HigherViewersDrawCoarserFinestLevels)
{
    const PyramidGeometry g(8193, 8193, 65);
    ClipmapWindows w(g, ClipmapSettings{});
    const double fov = 60.0 * 3.14159265358979 / 180.0;
    int previous = w.levelCount() - 1;
    EXPECT_EQ(finestDrawnLevel(w, 30.0, 10.0, fov, 1080), previous); // low: all of them
    for (double h = 10.0; h < 1e7; h *= 1.7) {
        const int k = finestDrawnLevel(w, 30.0, h, fov, 1080);
        EXPECT_LE(k, previous) << h;
        EXPECT_GE(k, 0);
        if (k > 0) { // drawn: its triangles are 2 px under the viewer, the finer one's not
            const double pixel = h * std::tan(fov / 1080.0);
            EXPECT_GE(30.0 * double(w.level(k).step), 2.0 * pixel);
            if (k + 1 < w.levelCount()) {
                EXPECT_LT(30.0 * double(w.level(k + 1).step), 2.0 * pixel);
            }
        }
        previous = k;
    }
    EXPECT_EQ(previous, 0); // from orbit only the coarsest
}

// --- Footprints ---------------------------------------------------------------------------

TEST(ClipmapFootprints, AreSixteenBitGridsOfTheThesisSizes)
{
    for (const int m : {16, 64, 256}) {
        for (int k = 0; k < kFootprintKinds; ++k) {
            const Footprint f = makeFootprint(FootprintKind(k), m);
            const size_t vertices = f.vertices.size() / 2;
            ASSERT_LE(vertices, 65536u);
            for (uint16_t i : f.indices)
                ASSERT_LT(i, vertices);
            ASSERT_EQ(f.indices.size() % 3, 0u);
            for (size_t v = 0; v < vertices; ++v) {
                EXPECT_LT(f.vertices[2 * v], f.width);
                EXPECT_LT(f.vertices[2 * v + 1], f.height);
            }
        }
        EXPECT_EQ(makeFootprint(FootprintKind::Block, m).triangles(),
                  size_t(2 * (m - 1) * (m - 1)));
        EXPECT_EQ(makeFootprint(FootprintKind::Perimeter, m).triangles(), size_t(2 * (4 * m - 2)));
    }
    EXPECT_THROW(makeFootprint(FootprintKind::Block, 257), Error);
    const std::vector<FootprintPiece> ring = levelPieces(64, false, 0, 1, true);
    EXPECT_EQ(std::count_if(ring.begin(), ring.end(),
                            [](const FootprintPiece& p) { return p.kind == FootprintKind::Block; }),
              12);
}

// Cells of an n × n window covered by a level's pieces (count per cell), perimeter left out
// (it covers no area).
std::vector<int> coveredCells(int m, const std::vector<FootprintPiece>& pieces)
{
    const int cells = 4 * m - 2;
    std::vector<int> count(size_t(cells) * cells, 0);
    for (const FootprintPiece& p : pieces) {
        if (p.kind == FootprintKind::Perimeter)
            continue;
        for (int y = 0; y + 1 < p.height; ++y)
            for (int x = 0; x + 1 < p.width; ++x)
                ++count[size_t(p.y + y) * cells + p.x + x];
    }
    return count;
}

TEST(ClipmapFootprints, ARingAndTheFinerLevelCoverTheWindowExactlyOnce)
{
    for (const int m : {16, 64}) {
        const int cells = 4 * m - 2;
        const std::vector<int> full = coveredCells(m, levelPieces(m, true, 0, 0, false));
        for (int c : full)
            ASSERT_EQ(c, 1) << "the filled level";
        for (int fx = 0; fx < 2; ++fx)
            for (int fy = 0; fy < 2; ++fy) {
                const std::vector<int> ring = coveredCells(m, levelPieces(m, false, fx, fy, true));
                for (int y = 0; y < cells; ++y)
                    for (int x = 0; x < cells; ++x) {
                        // The finer level: 2m − 1 cells from m − 1 + finer.
                        const bool finer = x >= m - 1 + fx && x < 3 * m - 2 + fx &&
                                           y >= m - 1 + fy && y < 3 * m - 2 + fy;
                        ASSERT_EQ(ring[size_t(y) * cells + x] + (finer ? 1 : 0), 1)
                            << "m " << m << " finer " << fx << fy << " cell " << x << "," << y;
                    }
            }
    }
}

// Every triangle of levels [first, L) placed about a viewer, as finest-grid integer corners;
// triangles with two identical corners (none expected) and the rest counted per edge.
TEST(ClipmapFootprints, NestedLevelsAreWatertightWithThePerimeterTriangles)
{
    const PyramidGeometry g(4097, 4097, 65);
    ClipmapSettings s;
    s.n = 63;
    ClipmapWindows w(g, s);
    const int m = s.m();
    std::map<FootprintKind, Footprint> footprints;
    for (int k = 0; k < kFootprintKinds; ++k)
        footprints.emplace(FootprintKind(k), makeFootprint(FootprintKind(k), m));
    std::mt19937 rng(2);
    std::uniform_real_distribution<double> u(500.0, 3500.0);
    for (int trial = 0; trial < 12; ++trial) {
        w.place(u(rng), u(rng));
        const int L = w.levelCount();
        const int first = trial % 3;          // the coarsest drawn level
        const int finest = L - 1 - trial % 2; // the finest drawn (filled) level
        using Point = std::pair<int64_t, int64_t>;
        std::map<std::pair<Point, Point>, int> edges;
        size_t degenerate = 0;
        for (int k = first; k <= finest; ++k) {
            const ClipmapLevel& l = w.level(k);
            for (const FootprintPiece& p :
                 levelPieces(m, k == finest, l.finer_x, l.finer_y, k > first)) {
                const Footprint& f = footprints.at(p.kind);
                auto corner = [&](uint16_t i) {
                    return Point{l.origin_x + (p.x + f.vertices[2 * i]) * l.step,
                                 l.origin_y + (p.y + f.vertices[2 * i + 1]) * l.step};
                };
                for (size_t t = 0; t < f.indices.size(); t += 3) {
                    Point c[3] = {corner(f.indices[t]), corner(f.indices[t + 1]),
                                  corner(f.indices[t + 2])};
                    if (c[0] == c[1] || c[1] == c[2] || c[0] == c[2]) {
                        ++degenerate;
                        continue;
                    }
                    for (int e = 0; e < 3; ++e) {
                        Point a = c[e], b = c[(e + 1) % 3];
                        if (b < a)
                            std::swap(a, b);
                        ++edges[{a, b}];
                    }
                }
            }
        }
        EXPECT_EQ(degenerate, 0u);
        const ClipmapLevel& outer = w.level(first);
        const int64_t x0 = outer.origin_x, y0 = outer.origin_y;
        const int64_t x1 = x0 + (s.n - 1) * outer.step, y1 = y0 + (s.n - 1) * outer.step;
        size_t open = 0, bad = 0;
        for (const auto& [edge, count] : edges) {
            const auto& [a, b] = edge;
            const bool border = (a.first == b.first && (a.first == x0 || a.first == x1)) ||
                                (a.second == b.second && (a.second == y0 || a.second == y1));
            if (border && count == 1)
                ++open;
            else if (count != 2) {
                ++bad;
                if (bad == 1)
                    ADD_FAILURE() << "trial " << trial << ": edge (" << a.first << "," << a.second
                                  << ")-(" << b.first << "," << b.second << ") used " << count;
            }
        }
        EXPECT_EQ(bad, 0u) << "trial " << trial;
        EXPECT_EQ(open, size_t(4 * (s.n - 1))) << "trial " << trial;
    }
}

} // namespace
