// Scheme clipmaps' residency policy (lod/clipmap_selector.h), without GL: level textures
// simulated as toroidal arrays of "which sample is here", written only through takeWrites,
// must hold exactly their windows after any walk and any residency; a level is drawn only
// when it and every coarser one are complete; nothing resident but the root still draws the
// decimated levels; prefetch wants the coming strips; hostile cameras are handled.
#include "ridge/lod/clipmap_selector.h"

#include "ridge/core/error.h"
#include "ridge/lod/ellipsoid.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <set>
#include <string>
#include <tuple>

using namespace ridge;
using namespace ridge::lod;

namespace {

// A 2049 × 1537 grid of 65-sample patches at 30 m (6 archive levels).
struct Terrain {
    PyramidGeometry g{2049, 1537, 65};
    PatchQuadtree tree = make(g);

    static PatchQuadtree make(const PyramidGeometry& g)
    {
        std::vector<PatchBounds> bounds(size_t(g.patchCount()));
        for (int64_t i = 0; i < g.patchCount(); ++i)
            bounds[size_t(i)] = {0.f, 500.f, 1.f};
        return PatchQuadtree(TerrainFrame(g, 30.0, 30.0), bounds);
    }
    // A camera `height` m above finest sample (column, row), looking north-east and down.
    Camera at(double column, double row, double height) const
    {
        const TerrainFrame& f = tree.frame();
        const glm::dvec3 pos(f.xOf(column), f.yOf(row), height);
        return Camera(pos, pos + glm::dvec3(1000.0, 1000.0, -height), 60.0, {640, 360}, 1.0, 1e7);
    }
};

struct ById {
    bool operator()(PatchId a, PatchId b) const
    {
        return std::tie(a.level, a.y, a.x) < std::tie(b.level, b.y, b.x);
    }
};

SelectionSettings settings()
{
    SelectionSettings s;
    s.max_patches = 4096;
    return s;
}

// Level textures as the GL half keeps them: texel (i mod N, j mod N) of level k holds the
// level sample last written there.
struct Textures {
    int N;
    std::vector<std::vector<std::pair<int64_t, int64_t>>> texels;
    Textures(int levels, int n) : N(n + 1), texels(size_t(levels))
    {
        for (auto& t : texels)
            t.assign(size_t(N) * N, {std::numeric_limits<int64_t>::min(), 0});
    }
    void apply(const ClipmapSelector& s, const ClipmapWrite& w)
    {
        for (int64_t j = w.rect.y0; j < w.rect.y1; ++j)
            for (int64_t i = w.rect.x0; i < w.rect.x1; ++i) {
                // The write reads the patch the policy says holds the sample.
                ASSERT_EQ(s.patchOf(w.level, i, j), w.patch);
                const int64_t x = ((i % N) + N) % N, y = ((j % N) + N) % N;
                texels[size_t(w.level)][size_t(y * N + x)] = {i, j};
            }
    }
    // Whether level k's texture holds exactly its window.
    bool holdsWindow(const ClipmapSelector& s, int k) const
    {
        const LevelRect w = s.windows().level(k).window(s.windows().n());
        for (int64_t j = w.y0; j < w.y1; ++j)
            for (int64_t i = w.x0; i < w.x1; ++i) {
                const int64_t x = ((i % N) + N) % N, y = ((j % N) + N) % N;
                if (texels[size_t(k)][size_t(y * N + x)] != std::pair{i, j})
                    return false;
            }
        return true;
    }
};

TEST(ClipmapSelector, LevelTexturesHoldTheirWindowsWheneverTheyAreDrawn)
{
    Terrain t;
    ClipmapSettings cs;
    cs.n = 63;
    ClipmapSelector s(t.tree, cs);
    const int L = s.windows().levelCount();
    Textures tex(L, cs.n);
    std::mt19937 rng(9);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::set<PatchId, ById> resident{PatchId{0, 0, 0}};
    double c = 300.0, r = 400.0;
    int drawn_frames = 0;
    for (int frame = 0; frame < 400; ++frame) {
        c += 9.0 * (u(rng) - 0.3);
        r += 7.0 * (u(rng) - 0.3);
        Selection sel;
        s.select(t.at(c, r, 40.0 + 2000.0 * u(rng) * u(rng)), settings(), sel);
        // Streaming: some of what is wanted arrives, some old patches are evicted.
        for (const SelectedPatch& p : sel.patches)
            if (u(rng) < 0.8)
                resident.insert(p.id);
        for (auto it = resident.begin(); it != resident.end();)
            it = (it->level > 0 && u(rng) < 0.1) ? resident.erase(it) : std::next(it);
        std::vector<ClipmapWrite> writes;
        s.takeWrites([&](PatchId p) { return resident.count(p) > 0; }, writes);
        for (const ClipmapWrite& w : writes) {
            ASSERT_TRUE(resident.count(w.patch));
            tex.apply(s, w);
        }
        const int drawn = s.finestDrawn();
        ASSERT_GE(drawn, 0) << "the decimated coarsest level reads the root, always resident";
        ASSERT_LE(drawn, s.finestWanted());
        for (int k = 0; k <= drawn; ++k)
            ASSERT_TRUE(tex.holdsWindow(s, k)) << "frame " << frame << " level " << k;
        drawn_frames += drawn == s.finestWanted();
    }
    EXPECT_GT(drawn_frames, 100); // and the walk mostly draws everything it wants
}

TEST(ClipmapSelector, EverythingResidentDrawsEveryWantedLevelAtOnce)
{
    Terrain t;
    ClipmapSelector s(t.tree, ClipmapSettings{});
    Selection sel;
    s.select(t.at(1000.0, 700.0, 50.0), settings(), sel);
    EXPECT_EQ(s.finestWanted(), s.windows().levelCount() - 1); // 50 m up: all of them
    EXPECT_EQ(s.finestDrawn(), -1);                            // nothing written yet
    // Only the decimated levels (the root's) are ready before anything is written.
    std::vector<ClipmapWrite> writes;
    s.takeWrites([](PatchId p) { return p.level == 0; }, writes);
    const int decimated = [&] {
        int k = 0;
        while (k < s.windows().levelCount() && s.windows().level(k).pyramid_level <= 0)
            ++k;
        return k;
    }();
    EXPECT_EQ(s.finestDrawn(), decimated - 1);
    s.takeWrites([](PatchId) { return true; }, writes);
    EXPECT_EQ(s.finestDrawn(), s.finestWanted());
    EXPECT_EQ(s.pendingWrites(), 0u);
    // Standing still wants nothing more.
    s.select(t.at(1000.0, 700.0, 50.0), settings(), sel);
    EXPECT_TRUE(sel.patches.empty());
    EXPECT_EQ(s.shifts(), 0);
}

TEST(ClipmapSelector, PrefetchWantsTheStripsOfTheComingShiftsAndChangesNothing)
{
    Terrain t;
    ClipmapSelector s(t.tree, ClipmapSettings{});
    Selection sel;
    s.select(t.at(1000.0, 700.0, 50.0), settings(), sel);
    std::vector<ClipmapWrite> writes;
    s.takeWrites([](PatchId) { return true; }, writes);
    Selection ahead;
    s.preview(t.at(1300.0, 700.0, 50.0), settings(), ahead); // 300 samples east
    EXPECT_FALSE(ahead.patches.empty());
    for (const SelectedPatch& p : ahead.patches)
        if (p.id.level == t.g.finestLevel()) { // the finest level's new patches lie east
            EXPECT_GE(int64_t(p.id.x + 1) * 64, 1000 + 127 - 1) << p.id.x;
        }
    EXPECT_EQ(s.pendingWrites(), 0u); // preview changed nothing
    EXPECT_EQ(s.finestDrawn(), s.finestWanted());
}

TEST(ClipmapSelector, HighAndFarCamerasDeactivateFineLevelsAndHostileOnesAreRefusedOrClamped)
{
    Terrain t;
    ClipmapSelector s(t.tree, ClipmapSettings{});
    Selection sel;
    s.select(t.at(1000.0, 700.0, 50.0), settings(), sel);
    const int low = s.finestWanted();
    s.select(t.at(1000.0, 700.0, 60000.0), settings(), sel);
    EXPECT_LT(s.finestWanted(), low);
    // Far off the terrain: the windows stay on its border, the fine levels off.
    s.select(t.at(-50000.0, 700.0, 100.0), settings(), sel);
    EXPECT_EQ(s.centre().x, 0.0);
    EXPECT_LT(s.finestWanted(), low);
    SelectionSettings bad = settings();
    bad.epsilon_px = std::nan("");
    EXPECT_THROW(s.select(t.at(1000.0, 700.0, 50.0), bad, sel), Error);
}

} // namespace

namespace {

// A whole-Earth grid of `turn` columns a turn (and the repeated edge meridian), pole to pole,
// patches of 17 samples, flat bounds.
PatchQuadtree wrappingGlobe(int turn)
{
    GeodeticGrid grid;
    grid.lon0 = 0.0;
    grid.lat0 = std::numbers::pi / 2;
    grid.dlon = 2.0 * std::numbers::pi / turn;
    grid.dlat = -grid.dlon;
    grid.wrap_columns = turn;
    const PyramidGeometry g(turn + 1, turn / 2 + 1, 17);
    std::vector<PatchBounds> bounds(size_t(g.patchCount()), PatchBounds{0.f, 100.f, 1.f});
    return PatchQuadtree(TerrainFrame::ellipsoid(g, 1.0, 1.0, grid), bounds);
}

// A camera `height` m above (lon, lat), degrees, looking north-east and down.
Camera overGlobe(const PatchQuadtree& tree, double lon, double lat, double height)
{
    const Ellipsoid& e = tree.frame().geodetic().ellipsoid;
    constexpr double kDeg = std::numbers::pi / 180.0;
    const glm::dvec3 pos = geodeticToEcef(e, lon * kDeg, lat * kDeg, height);
    const glm::dvec3 at = geodeticToEcef(e, (lon + 0.5) * kDeg, (lat + 0.5) * kDeg, 0.0);
    return Camera(pos, at, 60.0, {640, 360}, 1.0, 1e8);
}

} // namespace

// On a globe whose columns go round the Earth the windows run on across the antimeridian:
// their columns are unwrapped, every write reads the turn's own samples (its wrap shift a
// whole number of turns, its patch the one holding the wrapped samples), the textures hold
// exactly their windows, and crossing the seam shifts the levels by the camera's motion
// alone, never rewrites them whole.
TEST(ClipmapSelector, WindowsWrapAcrossTheAntimeridianOfAGlobe)
{
    const int turn = 1024; // 64 finest patches of 16 columns a turn, 7 levels
    const PatchQuadtree tree = wrappingGlobe(turn);
    ClipmapSettings cs;
    cs.n = 127;
    ClipmapSelector s(tree, cs);
    ASSERT_EQ(s.turn(), turn);
    const int L = s.windows().levelCount();
    Textures tex(L, cs.n);
    const int64_t C = tree.geometry().cells();
    double last_centre = 0.0;
    // From 3° west of the seam to 3° east of it, a tenth of a degree (about 0.3 columns) at
    // a time, 20 km up.
    for (int step = 0; step <= 60; ++step) {
        const double lon = 357.0 + 0.1 * step;
        Selection sel;
        s.select(overGlobe(tree, lon, 30.0, 2.0e4), settings(), sel);
        std::vector<ClipmapWrite> writes;
        s.takeWrites([](PatchId) { return true; }, writes);
        int64_t written = 0;
        for (const ClipmapWrite& w : writes) {
            const int64_t t = turn / s.windows().level(w.level).step;
            ASSERT_EQ(w.wrap_shift % t, 0) << "a whole number of turns";
            ASSERT_GE(w.rect.x0 - w.wrap_shift, 0);
            ASSERT_LE(w.rect.x1 - w.wrap_shift, t) << "within one turn";
            if (w.patch.level > 0) { // the wrapped columns lie in the patch
                EXPECT_GE(w.rect.x0 - w.wrap_shift, int64_t(w.patch.x) * C);
                EXPECT_LE(w.rect.x1 - w.wrap_shift, int64_t(w.patch.x + 1) * C + 1);
            }
            tex.apply(s, w);
            if (w.level == L - 1)
                written += w.rect.area();
        }
        ASSERT_EQ(s.finestDrawn(), s.finestWanted());
        for (int k = 0; k < L; ++k)
            ASSERT_TRUE(tex.holdsWindow(s, k)) << "step " << step << " level " << k;
        const double centre = s.centre().x;
        if (step > 0) {
            EXPECT_LT(std::abs(centre - last_centre), 1.0) << "the centre jumped at " << lon;
            EXPECT_LT(written, int64_t(cs.n) * cs.n) << "the finest level rewritten at " << lon;
        }
        last_centre = centre;
    }
    EXPECT_GT(last_centre, turn) << "the windows ran on east across the seam";
}

// Every level's cells must divide the turn, or sample i and its copy a turn away differ; a
// pole row must be a row of every level, or the surface would end between a level's rows; and
// the coarsest window must go round, or a gap of meridians shows across a pole: such a globe
// is refused, naming the levels or the n that would do.
TEST(ClipmapSelector, AGlobeTheWindowsCannotLieOnIsRefusedNamingWhatWould)
{
    const PatchQuadtree tree = wrappingGlobe(1000); // 8 · 125 columns, the pole on row 4 · 125
    auto refusal = [&](int n, int levels) {
        ClipmapSettings cs;
        cs.n = n;
        cs.levels = levels;
        try {
            ClipmapSelector s(tree, cs);
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    // 7 levels: cells of 64 fit neither; 4: cells of 8 divide the turn, not the rows.
    EXPECT_NE(refusal(127, 0).find("turn of 1000 columns and the 500 rows"), std::string::npos)
        << refusal(127, 0);
    EXPECT_NE(refusal(127, 0).find("levels=3"), std::string::npos) << refusal(127, 0);
    EXPECT_NE(refusal(127, 4).find("divide the 500 rows to its south pole,"), std::string::npos)
        << refusal(127, 4);
    EXPECT_NE(refusal(127, 4).find("levels=3"), std::string::npos) << refusal(127, 4);
    // 3 levels fit, but windows of 127 span 126 · 4 = 504 columns of the 1000.
    EXPECT_NE(refusal(127, 3).find("span 504: use n=255"), std::string::npos) << refusal(127, 3);
    EXPECT_NE(refusal(63, 1).find("span 62: use n=1023"), std::string::npos) << refusal(63, 1);
    EXPECT_EQ(refusal(255, 3), ""); // cells of 4, 2, 1 columns and rows; 1016 columns round
}

// The levels a turn wide end at one meridian (turnCut): on the grid of every level cut, the
// narrower windows inside the turn and the turn inside the finest wide window, so both ends
// are drawn by one level; the coarser levels are left out once one reaches both poles.
TEST(ClipmapSelector, WideLevelsEndAtOneMeridianOnTheirGridAroundTheNarrowerWindows)
{
    const int turn = 1024;
    const PatchQuadtree tree = wrappingGlobe(turn);
    ClipmapSettings cs;
    cs.n = 127; // windows 126 · step: 1008 columns at step 8, 2016 at 16
    ClipmapSelector s(tree, cs);
    const ClipmapWindows& w = s.windows();
    for (const double lon : {3.0, 91.5, 181.0, 359.9})
        for (const double lat : {-80.0, 0.0, 45.0, 89.0}) {
            SCOPED_TRACE(std::to_string(lon) + ", " + std::to_string(lat));
            Selection sel;
            s.select(overGlobe(tree, lon, lat, 100.0), settings(), sel);
            std::vector<ClipmapWrite> writes;
            s.takeWrites([](PatchId) { return true; }, writes);
            const int finest = s.finestDrawn();
            ASSERT_EQ(finest, w.levelCount() - 1);
            const ClipmapTurnCut cut = s.turnCut(finest);
            ASSERT_TRUE(cut.cut);
            int wide = finest;
            while (126 * w.level(wide).step < turn)
                --wide;
            EXPECT_EQ(w.level(wide).step, 16);
            EXPECT_LE(cut.coarsest, wide);
            EXPECT_EQ(cut.west % w.level(cut.coarsest).step, 0) << "on every cut level's grid";
            const ClipmapLevel& narrow = w.level(wide + 1);
            EXPECT_LE(cut.west, narrow.origin_x);
            EXPECT_GE(cut.west + turn, narrow.origin_x + 126 * narrow.step);
            EXPECT_GE(cut.west, w.level(wide).origin_x);
            EXPECT_LE(cut.west + turn, w.level(wide).origin_x + 126 * w.level(wide).step);
            // The coarsest drawn reaches both poles' rows; the next finer one does not.
            const ClipmapLevel& c = w.level(cut.coarsest);
            EXPECT_LE(c.origin_y, 0);
            EXPECT_GE(c.origin_y + 126 * c.step, turn / 2);
        }
    // On the plane nothing wraps: nothing to cut.
    Terrain plane;
    ClipmapSelector p(plane.tree, cs);
    Selection sel;
    p.select(plane.at(1000.0, 700.0, 50.0), settings(), sel);
    EXPECT_FALSE(p.turnCut(p.windows().levelCount() - 1).cut);
}
