#include "ridge/lod/rings.h"

#include "ridge/core/error.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string>

namespace ridge::lod {

namespace {

constexpr uint8_t bitOf(EdgePosition e)
{
    return edgeBit(e);
}

using E = EdgePosition;
constexpr uint8_t kUp = bitOf(E::Up) | bitOf(E::UpLeft) | bitOf(E::UpRight);
constexpr uint8_t kRight = bitOf(E::Right) | bitOf(E::UpRight) | bitOf(E::DownRight);
constexpr uint8_t kDown = bitOf(E::Down) | bitOf(E::DownRight) | bitOf(E::DownLeft);
constexpr uint8_t kLeft = bitOf(E::Left) | bitOf(E::DownLeft) | bitOf(E::UpLeft);

// log2 of a power of two.
int log2Of(int v)
{
    int k = 0;
    while ((1 << (k + 1)) <= v)
        ++k;
    return k;
}

int positiveMod(int v, int m)
{
    const int r = v % m;
    return r < 0 ? r + m : r;
}

// The eight neighbours (dx, dy) and the stitch bits a coarser one at that offset asks of the
// tile: across an edge, that edge with its two corners; across a corner, the corner alone.
struct Neighbour {
    int dx, dy;
    uint8_t bits;
};
constexpr std::array<Neighbour, 8> kNeighbours = {{
    {0, -1, kUp},
    {1, 0, kRight},
    {0, 1, kDown},
    {-1, 0, kLeft},
    {-1, -1, bitOf(E::UpLeft)},
    {1, -1, bitOf(E::UpRight)},
    {1, 1, bitOf(E::DownRight)},
    {-1, 1, bitOf(E::DownLeft)},
}};

} // namespace

const std::array<uint8_t, 9> kStitchTable = {
    0,              // Centre: the central patch and the first ring share the finest level
    kUp,            // North
    kUp | kRight,   // NorthEast
    kRight,         // East
    kRight | kDown, // SouthEast
    kDown,          // South
    kDown | kLeft,  // SouthWest
    kLeft,          // West
    kLeft | kUp,    // NorthWest
};

void RingsSettings::validate(const PyramidGeometry& geometry) const
{
    if (rings < 0 || rings > kMaxRings)
        throw Error("rings=" + std::to_string(rings) + " is outside [0, " +
                    std::to_string(kMaxRings) + "] (0: one ring per level)");
    if (vertex_step != 1 && vertex_step != 2)
        throw Error("vertex-step=" + std::to_string(vertex_step) + " must be 1 or 2");
    // The root must be drawable as tiles (the cover's last resort): a tile at level 0 spans
    // (n − 1)/(2^F·d) cells, at least one.
    const int cells = geometry.cells() / vertex_step;
    const int finest = geometry.finestLevel();
    if (cells < 1 || finest > log2Of(cells))
        throw Error("patches of " + std::to_string(geometry.patchSize()) +
                    " samples with vertex-step=" + std::to_string(vertex_step) +
                    " make static grids of " + std::to_string(cells) + " cells, too few for " +
                    std::to_string(finest + 1) + " levels: a tile drawn at the root needs " +
                    std::to_string(1 << finest) + " (build with a larger --patch" +
                    (vertex_step > 1 ? " or use vertex-step=1)" : ")"));
}

int ringsWrapTiles(const TerrainFrame& frame)
{
    const int64_t turn = frame.onEllipsoid() ? frame.geodetic().wrap_columns : 0;
    if (turn <= 0)
        return 0;
    const PyramidGeometry& g = frame.geometry();
    const int64_t span = g.cells(); // finest columns a tile
    if (turn % span == 0)
        return int(turn / span);
    // A patch size that would do: 2^k dividing the turn, and the root still drawable as a tile
    // (RingsSettings::validate) on the pyramid that patch makes.
    std::string fits;
    for (int cells = 256; cells >= 4 && fits.empty(); cells /= 2) { // patches 257 .. 5
        if (turn % cells != 0)
            continue;
        const PyramidGeometry other(g.width(), g.height(), cells + 1);
        if (other.finestLevel() < 31 && (1 << other.finestLevel()) <= cells)
            fits = std::to_string(cells + 1);
    }
    throw Error("rings cannot wrap a globe whose turn of " + std::to_string(turn) +
                " columns is not whole tiles of " + std::to_string(span) +
                " columns (its finest patches): " +
                (fits.empty() ? "no patch size gives tiles of 2^k columns that divide the turn "
                                "and still draw the root as a tile (2^k >= 2^levels); choose "
                                "another --lod, or --frame plane"
                              : "build with --patch " + fits));
}

RingsStructure::RingsStructure(const PatchQuadtree& tree, const RingsSettings& settings)
    : tree_(&tree)
{
    const PyramidGeometry& g = tree.geometry();
    settings.validate(g);
    wrap_tiles_ = ringsWrapTiles(tree.frame());
    finest_ = g.finestLevel();
    rings_ = settings.rings > 0 ? settings.rings : std::min(finest_ + 1, RingsSettings::kMaxRings);
    vertex_step_ = settings.vertex_step;
    cells_ = g.cells() / vertex_step_;
    tiles_x_ = g.patchesX(finest_);
    tiles_y_ = g.patchesY(finest_);
    cells_array_.assign(size_t(window()) * size_t(window()), RingCell{});
    // Any level's surface over a tile lies within Err(P) of the finest data (Err is measured
    // against the finest level), so the finest tile's range widened by the largest Err of its
    // ancestors bounds every level it may draw.
    auto bounds =
        std::make_shared<std::vector<std::array<float, 2>>>(size_t(tiles_x_) * size_t(tiles_y_));
    for (int y = 0; y < tiles_y_; ++y)
        for (int x = 0; x < tiles_x_; ++x) {
            const PatchId tile{finest_, x, y};
            float err = 0.f;
            for (PatchId p = tile;; p = p.parent()) {
                err = std::max(err, tree.bounds(p).err);
                if (p.level == 0)
                    break;
            }
            const PatchBounds& b = tree.bounds(tile);
            (*bounds)[size_t(y) * size_t(tiles_x_) + size_t(x)] = {b.min_height - err,
                                                                   b.max_height + err};
        }
    bounds_ = std::move(bounds);
}

int RingsStructure::cellsAt(int level) const
{
    return cells_ >> (finest_ - level);
}

int RingsStructure::levelOfRing(int ring, int coarser) const
{
    const int r = std::min(ring, rings_);
    return std::max(0, finest_ - std::max(r - 1, 0) - coarser);
}

void RingsStructure::tileBounds(int x, int y, float& min_height, float& max_height) const
{
    const std::array<float, 2>& b = (*bounds_)[size_t(y) * size_t(tiles_x_) + size_t(x)];
    min_height = b[0];
    max_height = b[1];
}

int RingsStructure::dxOf(int x) const
{
    const int dx = x - centre_x_;
    if (wrap_tiles_ <= 0)
        return dx;
    return positiveMod(dx + wrap_tiles_ / 2, wrap_tiles_) - wrap_tiles_ / 2;
}

int RingsStructure::columnAt(int x, int dx) const
{
    const int c = x + dx;
    if (wrap_tiles_ > 0)
        return positiveMod(c, wrap_tiles_);
    return c >= 0 && c < tiles_x_ ? c : -1;
}

RingCell& RingsStructure::at(int x, int y)
{
    const int w = window();
    return cells_array_[size_t(positiveMod(y, w)) * size_t(w) + size_t(positiveMod(x, w))];
}

const RingCell& RingsStructure::cell(int x, int y) const
{
    if (std::abs(dxOf(x)) > rings_ || std::abs(y - centre_y_) > rings_)
        throw Error("rings structure: tile (" + std::to_string(x) + ", " + std::to_string(y) +
                    ") is outside the window");
    const int w = window(), vx = centre_vx_ + dxOf(x);
    return cells_array_[size_t(positiveMod(y, w)) * size_t(w) + size_t(positiveMod(vx, w))];
}

void RingsStructure::assign(RingCell& c, int x, int y) const
{
    c.tile_x = x;
    c.tile_y = y;
    c.exists = x >= 0 && y >= 0 && x < tiles_x_ && y < tiles_y_;
    if (c.exists)
        tileBounds(x, y, c.min_height, c.max_height);
}

int RingsStructure::ringOf(int x, int y) const
{
    return std::max(std::abs(dxOf(x)), std::abs(y - centre_y_));
}

Orientation RingsStructure::orientationOf(int x, int y) const
{
    const int dx = dxOf(x), dy = y - centre_y_; // rows grow south: dy < 0 is north
    const int ring = std::max(std::abs(dx), std::abs(dy));
    if (ring == 0)
        return Orientation::Centre;
    if (dy == -ring)
        return dx == ring    ? Orientation::NorthEast
               : dx == -ring ? Orientation::NorthWest
                             : Orientation::North;
    if (dy == ring)
        return dx == ring    ? Orientation::SouthEast
               : dx == -ring ? Orientation::SouthWest
                             : Orientation::South;
    return dx > 0 ? Orientation::East : Orientation::West;
}

void RingsStructure::updateRings(int i, int j)
{
    if (!tree_)
        throw Error("rings structure: not constructed");
    const int previous_x = centre_x_;
    centre_x_ = std::clamp(i, 0, tiles_x_ - 1);
    // Unwrapped, the centre moves the short way round: across the seam to a neighbour too.
    centre_vx_ = wrap_tiles_ > 0 && built_ ? centre_vx_ - dxOf(previous_x) : centre_x_;
    centre_y_ = std::clamp(j, 0, tiles_y_ - 1);
    // Toroidal addressing: a tile keeps its cell while it stays in the window, so after a
    // move to a neighbour of the centre only the row and column that wrapped hold new tiles;
    // after a jump (or the first call) every cell does.
    refreshed_ = 0;
    for (int y = centre_y_ - rings_; y <= centre_y_ + rings_; ++y)
        for (int x = centre_vx_ - rings_; x <= centre_vx_ + rings_; ++x) {
            // x runs unwrapped through the window; the cell holds the tile it wraps to.
            RingCell& c = at(x, y);
            const int tile_x = wrap_tiles_ > 0 ? positiveMod(x, wrap_tiles_) : x;
            if (!built_ || c.tile_x != tile_x || c.tile_y != y) {
                assign(c, tile_x, y);
                ++refreshed_;
            }
            c.ring = ringOf(tile_x, y);
            c.orientation = orientationOf(tile_x, y);
        }
    built_ = true;
}

RingsSelector::RingsSelector(const PatchQuadtree& tree, const RingsSettings& settings)
    : tree_(tree), structure_(tree, settings), preview_structure_(tree, settings)
{
    const size_t tiles = size_t(structure_.tilesX()) * size_t(structure_.tilesY());
    tiles_.resize(tiles);
    preview_tiles_.resize(tiles);
    drawn_.reserve(tiles);
}

void RingsSelector::centreOn(RingsStructure& s, const Camera& camera) const
{
    // The tile under the camera, clamped to the terrain (a camera far off it — any finite
    // position — centres on the nearest edge tile; the array is never indexed outside).
    const TerrainFrame& f = tree_.frame();
    const double span = double(tree_.geometry().cells());
    // Grid coordinates under the camera through the frame (the plane's x, y; on a globe the
    // point below it on the ellipsoid).
    const glm::dvec3 grid = f.gridOf(camera.position());
    const double column = grid.x / span;
    const double row = grid.y / span;
    auto tileIndex = [](double v, int count) {
        if (!(v >= 0.0))
            return 0; // negative or NaN
        return v >= double(count - 1) ? count - 1 : int(v);
    };
    s.updateRings(tileIndex(column, s.tilesX()), tileIndex(row, s.tilesY()));
}

int RingsSelector::levelAt(int x, int y, const std::vector<TileState>& tiles, bool desired) const
{
    const TileState& t = tiles[size_t(y) * size_t(structure_.tilesX()) + size_t(x)];
    return desired ? t.desired : t.level;
}

// The stitch bits tile t needs: every edge and corner it shares with a coarser tile.
// Whether tile t and its eight neighbours all exist and draw their rings' levels.
bool RingsSelector::atRingLevels(size_t t) const
{
    const int w = structure_.tilesX(), h = structure_.tilesY();
    const int x = int(t % size_t(w)), y = int(t / size_t(w));
    if (tiles_[t].level != tiles_[t].desired)
        return false;
    for (const Neighbour& n : kNeighbours) {
        const int nx = structure_.columnAt(x, n.dx), ny = y + n.dy;
        if (nx < 0 || ny < 0 || ny >= h)
            return false;
        const TileState& u = tiles_[size_t(ny) * size_t(w) + size_t(nx)];
        if (u.level != u.desired)
            return false;
    }
    return true;
}

uint8_t RingsSelector::stitchOf(size_t t, const std::vector<TileState>& tiles,
                                bool at_desired) const
{
    const int w = structure_.tilesX(), h = structure_.tilesY();
    const int x = int(t % size_t(w)), y = int(t / size_t(w));
    const int own = at_desired ? tiles[t].desired : tiles[t].level;
    uint8_t bits = 0;
    for (const Neighbour& n : kNeighbours) {
        const int nx = structure_.columnAt(x, n.dx), ny = y + n.dy;
        if (nx >= 0 && ny >= 0 && ny < h && levelAt(nx, ny, tiles, at_desired) < own)
            bits |= n.bits;
    }
    return bits;
}

void RingsSelector::listPatches(const RingsStructure& s, const std::vector<TileState>& tiles,
                                bool use_desired, int /*coarser*/, Selection& out) const
{
    out.patches.clear();
    const PyramidGeometry& g = tree_.geometry();
    for (size_t t = 0; t < tiles.size(); ++t) {
        const TileState& ts = tiles[t];
        if (!ts.visible)
            continue;
        const int x = int(t % size_t(s.tilesX())), y = int(t / size_t(s.tilesX()));
        const int level = use_desired ? ts.desired : ts.level;
        // Inner rings first within a level.
        const double rank = double(s.rings() + 2 - std::min(int(ts.ring), s.rings() + 1));
        out.patches.push_back({ancestorOf(x, y, level), 0.0, ts.visibility, 0.0, rank});
        if (level > 0 && stitchOf(t, tiles, use_desired))
            out.patches.push_back({ancestorOf(x, y, level - 1), 0.0, ts.visibility, 0.0, rank});
    }
    // One entry per patch, the highest rank and least certain visibility.
    std::sort(out.patches.begin(), out.patches.end(),
              [&](const SelectedPatch& a, const SelectedPatch& b) {
                  const int64_t ka = g.patchIndex(a.id), kb = g.patchIndex(b.id);
                  return ka != kb ? ka < kb : a.rank > b.rank;
              });
    size_t kept = 0;
    for (size_t k = 0; k < out.patches.size(); ++k) {
        if (kept > 0 && out.patches[kept - 1].id == out.patches[k].id) {
            SelectedPatch& p = out.patches[kept - 1];
            p.visibility = std::min(p.visibility, out.patches[k].visibility);
        } else {
            out.patches[kept++] = out.patches[k];
        }
    }
    out.patches.resize(kept);
}

void RingsSelector::desire(const RingsStructure& s, const Camera& camera,
                           const SelectionSettings& settings, std::vector<TileState>& tiles,
                           Selection& out) const
{
    settings.validate();
    const Frustum frustum(camera);
    const TerrainFrame& f = tree_.frame();
    const double k = settings.exaggeration;
    out.visited = 0;
    out.culled = 0;
    for (int y = 0; y < s.tilesY(); ++y)
        for (int x = 0; x < s.tilesX(); ++x) {
            TileState& t = tiles[size_t(y) * size_t(s.tilesX()) + size_t(x)];
            t.ring = int8_t(std::min(s.ringOf(x, y), 127));
            t.visibility = Visibility::Inside;
            float lo = 0.f, hi = 0.f;
            if (std::abs(s.dxOf(x)) <= s.rings() && std::abs(y - s.centreY()) <= s.rings()) {
                const RingCell& c = s.cell(x, y); // bounds held by the structure's cell
                lo = c.min_height;
                hi = c.max_height;
            } else {
                s.tileBounds(x, y, lo, hi);
            }
            ++out.visited;
            if (settings.cull) {
                const Box box = f.patchBox(PatchId{s.finestLevel(), x, y}, k * lo, k * hi);
                t.visibility = frustum.classify(box);
            }
            t.visible = t.visibility != Visibility::Outside;
            out.culled += !t.visible;
        }
    // Coarser by whole levels until the patches fit the slots (the quadtree walk raises ε).
    for (int coarser = 0;; ++coarser) {
        for (size_t t = 0; t < tiles.size(); ++t)
            tiles[t].desired = int8_t(s.levelOfRing(tiles[t].ring, coarser));
        listPatches(s, tiles, true, coarser, out);
        out.levels_coarser = coarser;
        if (out.patches.size() <= settings.max_patches || s.levelOfRing(0, coarser) == 0)
            break;
    }
    out.epsilon_px = settings.epsilon_px; // rings promise no screen-space bound
    out.texel_px = settings.texel_px;
}

void RingsSelector::select(const Camera& camera, const SelectionSettings& settings, Selection& out)
{
    centreOn(structure_, camera);
    desire(structure_, camera, settings, tiles_, out);
    coarser_ = out.levels_coarser;
}

void RingsSelector::preview(const Camera& camera, const SelectionSettings& settings,
                            Selection& out) const
{
    preview_structure_ = structure_; // capacity kept: no allocation once sized
    centreOn(preview_structure_, camera);
    desire(preview_structure_, camera, settings, preview_tiles_, out);
}

void RingsSelector::cover(const Selection& /*desired*/,
                          const std::function<bool(PatchId)>& resident, ResidentCover& out)
{
    const int w = structure_.tilesX(), h = structure_.tilesY();
    // The finest resident ancestor of tile t at `level` or coarser (the root is resident).
    auto finestResident = [&](size_t t, int level) {
        const int x = int(t % size_t(w)), y = int(t / size_t(w));
        while (level > 0 && !resident(ancestorOf(x, y, level)))
            --level;
        return int8_t(level);
    };
    for (size_t t = 0; t < tiles_.size(); ++t)
        tiles_[t].level =
            tiles_[t].visible ? finestResident(t, tiles_[t].desired) : tiles_[t].desired;
    // Lower until every two touching tiles differ by at most one level and every tile that
    // meets a coarser one has that level resident (its stitched edges read it). Levels only
    // fall and the root needs nothing coarser, so this ends.
    for (bool changed = true; changed;) {
        changed = false;
        for (size_t t = 0; t < tiles_.size(); ++t) {
            const int x = int(t % size_t(w)), y = int(t / size_t(w));
            int lowest = tiles_[t].level;
            for (const Neighbour& n : kNeighbours) {
                const int nx = structure_.columnAt(x, n.dx), ny = y + n.dy;
                if (nx >= 0 && ny >= 0 && ny < h)
                    lowest = std::min(lowest, levelAt(nx, ny, tiles_, false));
            }
            TileState& ts = tiles_[t];
            int target = ts.level;
            if (ts.level > lowest + 1)
                target = lowest + 1;
            else if (ts.visible && lowest < ts.level && !resident(ancestorOf(x, y, ts.level - 1)))
                target = ts.level - 1;
            if (target != ts.level) {
                ts.level = ts.visible ? finestResident(t, target) : int8_t(target);
                changed = true;
            }
        }
    }
    drawn_.clear();
    lowered_ = 0;
    for (size_t t = 0; t < tiles_.size(); ++t) {
        const TileState& ts = tiles_[t];
        if (!ts.visible)
            continue;
        lowered_ += ts.level < ts.desired;
        const int x = int(t % size_t(w)), y = int(t / size_t(w));
        RingTile tile{x,
                      y,
                      ts.ring,
                      ts.level,
                      stitchOf(t, tiles_, false),
                      false,
                      Orientation::Centre,
                      ts.visibility};
        if (atRingLevels(t)) {
            tile.by_table = true;
            if (structure_.outerRingCoarser(ts.ring, coarser_))
                tile.orientation = structure_.orientationOf(x, y);
        }
        drawn_.push_back(tile);
    }
    listPatches(structure_, tiles_, false, coarser_, cover_patches_);
    out.patches.swap(cover_patches_.patches);
    out.missing = lowered_;
}

} // namespace ridge::lod
