#include "ridge/lod/clipmap_selector.h"

#include "ridge/core/error.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace ridge::lod {
namespace {

LevelRect intersect(const LevelRect& a, const LevelRect& b)
{
    LevelRect r{std::max(a.x0, b.x0), std::max(a.y0, b.y0), std::min(a.x1, b.x1),
                std::min(a.y1, b.y1)};
    if (r.x1 <= r.x0 || r.y1 <= r.y0)
        return {};
    return r;
}

// Half-open ranges of an archive level's samples by patch: patch p takes [p·C, (p + 1)·C),
// the first everything below, the last everything above (edge samples beyond the terrain).
struct PatchRange {
    int64_t lo, hi;
};
PatchRange rangeOf(int p, int last, int64_t cells)
{
    constexpr int64_t kFar = int64_t{1} << 60;
    return {p == 0 ? -kFar : p * cells, p == last ? kFar : (p + 1) * cells};
}

} // namespace

void checkClipmapGlobe(const TerrainFrame& f, int n, int levels)
{
    // On the globe two lines must be lines of every level's grid, so that the coarsest cells
    // (2^(L − 1) samples) divide their distance from column and row 0: a level's sample i and
    // i + (its samples a turn) are one sample only if its cells divide the turn; and a pole
    // on the last row ends the surface at one point only along a row of every level (row 0
    // is). The levels that fit both, and what failed:
    if (!f.onEllipsoid())
        return;
    const int64_t turn = f.geodetic().wrap_columns;
    const int64_t last_row = f.geometry().height() - 1;
    int fits = ClipmapSettings::kMaxLevels;
    std::string failed;
    auto onGrid = [&](int64_t distance, const std::string& what) {
        int most = 1; // 2^(most − 1) divides the distance
        while (most < ClipmapSettings::kMaxLevels && distance % (int64_t{1} << most) == 0)
            ++most;
        if (levels > most)
            failed += (failed.empty() ? "" : " and ") + what;
        fits = std::min(fits, most);
    };
    if (turn > 0)
        onGrid(turn, "its turn of " + std::to_string(turn) + " columns");
    if (f.poleRow(double(last_row)))
        onGrid(last_row, "the " + std::to_string(last_row) + " rows to its south pole");
    if (!failed.empty())
        throw Error("clipmaps on this globe need cells that divide " + failed + ", but the " +
                    "coarsest of " + std::to_string(levels) + " levels has " +
                    std::to_string(int64_t{1} << (levels - 1)) +
                    ": use levels=" + std::to_string(fits) + " or fewer, or --frame plane");
    // And the coarsest window must go round: a narrower one leaves a gap of meridians
    // opposite the viewer, which shows across a pole.
    const int64_t span = int64_t(n - 1) << (levels - 1);
    if (turn > 0 && span < turn) {
        int wider = n;
        while (wider < ClipmapSettings::kMaxN && (int64_t(wider - 1) << (levels - 1)) < turn)
            wider = 2 * wider + 1;
        const bool enough = (int64_t(wider - 1) << (levels - 1)) >= turn;
        throw Error("clipmaps on this globe need the coarsest window to go round its turn of " +
                    std::to_string(turn) + " columns, but " + std::to_string(levels) +
                    " levels of n " + std::to_string(n) + " span " + std::to_string(span) +
                    (enough ? ": use n=" + std::to_string(wider)
                            : ": no n does with these levels; build with a larger --patch") +
                    ", or --frame plane");
    }
}

ClipmapSelector::ClipmapSelector(const PatchQuadtree& tree, const ClipmapSettings& settings)
    : tree_(tree), windows_(tree.geometry(), settings)
{
    if (tree.geometry().patchesX(0) != 1 || tree.geometry().patchesY(0) != 1)
        throw Error("clipmaps: internal: level 0 must be one patch");
    const TerrainFrame& f = tree.frame();
    turn_ = f.onEllipsoid() ? f.geodetic().wrap_columns : 0;
    checkClipmapGlobe(f, windows_.n(), windows_.levelCount());
    pending_.resize(size_t(windows_.levelCount()));
}

int64_t ClipmapSelector::decimation(int level) const
{
    const int l = windows_.level(level).pyramid_level;
    return l >= 0 ? 1 : int64_t{1} << -l;
}

PatchId ClipmapSelector::patchOf(int level, int64_t i, int64_t j) const
{
    const int l = windows_.level(level).pyramid_level;
    if (l <= 0)
        return PatchId{0, 0, 0};
    if (turn_ > 0)
        i -= floorDiv(i, samplesPerTurn(level)) * samplesPerTurn(level);
    const PyramidGeometry& g = tree_.geometry();
    const int64_t C = g.cells();
    const int x = int(std::clamp<int64_t>(floorDiv(i, C), 0, g.patchesX(l) - 1));
    const int y = int(std::clamp<int64_t>(floorDiv(j, C), 0, g.patchesY(l) - 1));
    return PatchId{l, x, y};
}

void ClipmapSelector::splitByPatch(int level, const LevelRect& rect,
                                   std::vector<ClipmapWrite>& out) const
{
    if (rect.area() <= 0)
        return;
    if (turn_ <= 0) {
        splitWithinTurn(level, rect, 0, out);
        return;
    }
    const int64_t t = samplesPerTurn(level);
    for (int64_t a = rect.x0; a < rect.x1;) {
        const int64_t shift = floorDiv(a, t) * t;
        const int64_t b = std::min(rect.x1, shift + t);
        splitWithinTurn(level, {a - shift, rect.y0, b - shift, rect.y1}, shift, out);
        a = b;
    }
}

void ClipmapSelector::splitWithinTurn(int level, const LevelRect& rect, int64_t shift,
                                      std::vector<ClipmapWrite>& out) const
{
    const int l = windows_.level(level).pyramid_level;
    if (l <= 0) {
        out.push_back(
            {level, PatchId{0, 0, 0}, {rect.x0 + shift, rect.y0, rect.x1 + shift, rect.y1}, shift});
        return;
    }
    const PyramidGeometry& g = tree_.geometry();
    const int64_t C = g.cells();
    const PatchId first = patchOf(level, rect.x0, rect.y0);
    const PatchId last = patchOf(level, rect.x1 - 1, rect.y1 - 1);
    for (int y = first.y; y <= last.y; ++y)
        for (int x = first.x; x <= last.x; ++x) {
            const PatchRange rx = rangeOf(x, g.patchesX(l) - 1, C);
            const PatchRange ry = rangeOf(y, g.patchesY(l) - 1, C);
            const LevelRect part = intersect(rect, {rx.lo, ry.lo, rx.hi, ry.hi});
            if (part.area() > 0)
                out.push_back({level,
                               PatchId{l, x, y},
                               {part.x0 + shift, part.y0, part.x1 + shift, part.y1},
                               shift});
        }
}

glm::dvec2 ClipmapSelector::centreOf(const Camera& camera, double exaggeration,
                                     double& distance) const
{
    const TerrainFrame& f = tree_.frame();
    const glm::dvec3 grid = f.gridOf(camera.position());
    const double W = f.geometry().width() - 1, H = f.geometry().height() - 1;
    glm::dvec2 centre(std::clamp(grid.x, 0.0, W), std::clamp(grid.y, 0.0, H));
    double column = centre.x; // on the terrain
    if (turn_ > 0) {
        // The copy of the camera's column nearest the windows: they move on across the seam.
        const double t = double(turn_);
        column = std::clamp(grid.x - t * std::floor(grid.x / t), 0.0, W);
        centre.x = windows_.placed() ? grid.x + t * std::round((centre_.x - grid.x) / t) : column;
    }
    // Off the terrain: the ground distance to its border; above it: the height over the
    // highest sample of the finest patch under the viewer (so a level is never dropped for a
    // viewer nearer to the ground than it seems).
    const PyramidGeometry& g = f.geometry();
    const int F = g.finestLevel();
    const int64_t C = g.cells();
    const PatchId under{F, int(std::min<int64_t>(int64_t(column) / C, g.patchesX(F) - 1)),
                        int(std::min<int64_t>(int64_t(centre.y) / C, g.patchesY(F) - 1))};
    const double above = grid.z - exaggeration * double(tree_.bounds(under).max_height);
    const double off_x = turn_ > 0 ? 0.0 : grid.x - centre.x;
    const double off = std::hypot(off_x * f.spacingX(), (grid.y - centre.y) * f.spacingY());
    distance = std::hypot(std::max(above, 0.0), off);
    return centre;
}

int ClipmapSelector::wantedFinest(const Camera& camera, double distance) const
{
    const TerrainFrame& f = tree_.frame();
    return finestDrawnLevel(windows_, std::max(f.spacingX(), f.spacingY()), distance, camera.fovY(),
                            camera.viewport().height);
}

void ClipmapSelector::want(const std::vector<ClipmapWrite>& writes, size_t max_patches,
                           Selection& out) const
{
    for (const ClipmapWrite& w : writes) {
        if (out.patches.size() >= max_patches)
            return;
        const bool seen = std::any_of(out.patches.begin(), out.patches.end(),
                                      [&](const SelectedPatch& s) { return s.id == w.patch; });
        if (seen)
            continue;
        SelectedPatch s;
        s.id = w.patch;
        s.visibility = Visibility::Intersecting;
        // Coarse levels first (the planner also orders by quadtree level; this orders the
        // decimated levels, which share the root, and keeps each level's writes in order).
        s.rank = double(windows_.levelCount() - w.level);
        out.patches.push_back(s);
    }
}

void ClipmapSelector::select(const Camera& camera, const SelectionSettings& settings,
                             Selection& out)
{
    settings.validate();
    out = Selection{};
    out.epsilon_px = settings.epsilon_px;
    out.texel_px = settings.texel_px;
    double distance = 0.0;
    centre_ = centreOf(camera, settings.exaggeration, distance);
    shifts_ = windows_.place(centre_.x, centre_.y);
    for (int k = 0; k < windows_.levelCount(); ++k) {
        const std::vector<LevelRect>& strip = windows_.updateRegions(k);
        if (strip.empty())
            continue;
        // What was pending outside the new window is no longer needed.
        std::vector<ClipmapWrite>& pending = pending_[size_t(k)];
        const LevelRect window = windows_.level(k).window(windows_.n());
        std::vector<ClipmapWrite> kept;
        for (const ClipmapWrite& w : pending) {
            const LevelRect r = intersect(w.rect, window);
            if (r.area() > 0)
                kept.push_back({w.level, w.patch, r, w.wrap_shift});
        }
        pending = std::move(kept);
        for (const LevelRect& r : strip)
            splitByPatch(k, r, pending);
    }
    finest_wanted_ = wantedFinest(camera, distance);
    for (int k = 0; k <= finest_wanted_; ++k)
        want(pending_[size_t(k)], settings.max_patches, out);
}

void ClipmapSelector::preview(const Camera& camera, const SelectionSettings& settings,
                              Selection& out) const
{
    out = Selection{};
    out.epsilon_px = settings.epsilon_px;
    out.texel_px = settings.texel_px;
    double distance = 0.0;
    const glm::dvec2 centre = centreOf(camera, settings.exaggeration, distance);
    ClipmapWindows ahead = windows_;
    ahead.place(centre.x, centre.y);
    const int finest = wantedFinest(camera, distance);
    std::vector<ClipmapWrite> writes;
    for (int k = 0; k <= finest; ++k) {
        writes.insert(writes.end(), pending_[size_t(k)].begin(), pending_[size_t(k)].end());
        for (const LevelRect& r : ahead.updateRegions(k))
            splitByPatch(k, r, writes);
    }
    want(writes, settings.max_patches, out);
}

void ClipmapSelector::cover(const Selection& desired, const std::function<bool(PatchId)>& resident,
                            ResidentCover& out)
{
    // Nothing stands in for a missing patch: the level waits (finestDrawn) and the coarser
    // one shows. What is resident of the wanted set is kept until it is written.
    out.patches.clear();
    out.missing = 0;
    for (const SelectedPatch& p : desired.patches) {
        if (resident(p.id))
            out.patches.push_back(p);
        else
            ++out.missing;
    }
}

void ClipmapSelector::takeWrites(const std::function<bool(PatchId)>& resident,
                                 std::vector<ClipmapWrite>& out)
{
    out.clear();
    for (std::vector<ClipmapWrite>& pending : pending_) {
        auto waiting =
            std::stable_partition(pending.begin(), pending.end(),
                                  [&](const ClipmapWrite& w) { return !resident(w.patch); });
        out.insert(out.end(), waiting, pending.end());
        pending.erase(waiting, pending.end());
    }
}

int ClipmapSelector::finestDrawn() const
{
    int k = -1;
    while (k < finest_wanted_ && pending_[size_t(k + 1)].empty())
        ++k;
    return k;
}

ClipmapTurnCut ClipmapSelector::turnCut(int finest) const
{
    ClipmapTurnCut out;
    const int64_t T = turn_, n = windows_.n();
    if (T <= 0 || finest < 0)
        return out;
    auto width = [&](int k) { return (n - 1) * windows_.level(k).step; };
    // The finest wide level.
    int wide = finest;
    while (wide >= 0 && width(wide) < T)
        --wide;
    if (wide < 0)
        return out; // every drawn window is narrower than a turn: nothing overlaps
    // The coarsest level needed: the first from `wide` on whose rows reach both ends of the
    // terrain's (a level that does covers the whole turn; nothing coarser shows).
    const int64_t last_row = tree_.frame().geometry().height() - 1;
    int coarsest = wide;
    while (coarsest > 0) {
        const ClipmapLevel& l = windows_.level(coarsest);
        if (l.origin_y <= 0 && l.origin_y + width(coarsest) >= last_row)
            break;
        --coarsest;
    }
    // West: inside the finest wide window with the turn after it, and the narrower windows
    // inside the turn; on the coarsest cut level's grid.
    const ClipmapLevel& w = windows_.level(wide);
    int64_t lo = w.origin_x, hi = w.origin_x + width(wide) - T;
    if (wide < finest) {
        const ClipmapLevel& narrow = windows_.level(wide + 1);
        lo = std::max(lo, narrow.origin_x + width(wide + 1) - T);
        hi = std::min(hi, narrow.origin_x);
    }
    const int64_t s = windows_.level(coarsest).step;
    out.cut = true;
    out.west = -floorDiv(-lo, s) * s; // lo rounded up to the grid
    out.coarsest = coarsest;
    if (out.west > hi) // no line of that grid fits: draw the finest wide level alone
        out = {true, -floorDiv(-lo, w.step) * w.step, wide};
    return out;
}

size_t ClipmapSelector::pendingWrites() const
{
    size_t n = 0;
    for (const std::vector<ClipmapWrite>& p : pending_)
        n += p.size();
    return n;
}

} // namespace ridge::lod
