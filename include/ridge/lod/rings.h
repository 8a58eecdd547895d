#pragma once
// The rings structure of Erra, Scarano & Guida, "Fractal compression approach for efficient
// interactive terrain rendering on the GPU" (§4–6), over ridge's archive: the LOD policy of
// scheme `rings`, plain C++ (the GL half is src/render/schemes/rings_scheme.cpp).
//
// The terrain is cut into equal tiles — the archive's finest patches — and drawn as
// concentric square rings around the viewer: the central patch (ring 0) and the first ring
// at the finest level, each further ring one level coarser (a tile of ring r ≥ 1 draws the
// samples of its ancestor at level F − (r − 1), F the finest), the last ring's level on to
// the terrain's edge. A tile at level l is one of the static vertex grids: (n − 1)/(2^(F−l)·d)
// cells a side, d the vertex step (1: one vertex per sample; 2: the paper's 128² vertices for
// 256² tiles). Neighbouring rings differ by one level, and the finer side of every such edge
// is stitched to the coarser (§6, Figure 6): an odd edge vertex (w_odd) moves onto the
// previous even one, and every vertex on that edge takes its height from the coarser level,
// so both sides share bit-identical vertices and no skirt is needed. Which edges a tile
// stitches follows from its orientation relative to the central patch (kStitchTable, the
// paper's table).
//
// The structure is a (2R + 1)² array of cells addressed toroidally (tile x, y mod 2R + 1) and
// re-centred by updateRings(i, j): when the viewer moves into one of the eight neighbours of
// the central patch only the row and column of cells that wrap take new tiles (their bounds
// are read again); rings and orientations are recomputed, which is arithmetic.
//
// On a globe whose columns go round the Earth the tiles wrap too: tile x and x + T are one (T
// tiles a turn), rings, orientations and neighbours are measured the short way round, so the
// rings cross the antimeridian like any other meridian. That needs whole tiles a turn: the
// finest patch's columns must divide the turn's (ringsWrapTiles says why not).
//
// Streaming (RingsSelector::cover): while the tiles' patches arrive, each visible tile draws
// its finest resident ancestor, then levels are lowered until every two tiles that touch
// (across an edge or a corner) differ by at most one level and every tile that meets a coarser
// one has that coarser level resident: the stitching closes every edge of every cover, never a
// hole, never two levels across one edge.
#include "ridge/lod/patch_selector.h"

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

namespace ridge::lod {

// The paper's orientation of a patch relative to the central patch (Figure 4).
enum class Orientation : uint8_t {
    Centre,
    North,
    NorthEast,
    East,
    SouthEast,
    South,
    SouthWest,
    West,
    NorthWest
};

// The paper's y_pos: where a vertex of a tile's grid lies. Up is north (row 0), right east.
enum class EdgePosition : uint8_t {
    Inside,
    Up,
    Right,
    Down,
    Left,
    UpLeft,
    UpRight,
    DownRight,
    DownLeft
};

// Bits of a tile's stitch mask: edges (Up..Left) then corners (UpLeft..DownLeft) that take
// their heights from the coarser level.
constexpr uint8_t edgeBit(EdgePosition e)
{
    return uint8_t(1u << (int(e) - 1));
}

// The paper's table: which edge positions of a tile of each orientation are stitched to the
// coarser ring outside it (indexed by Orientation), corners of stitched edges included.
extern const std::array<uint8_t, 9> kStitchTable;

struct RingsSettings {
    static constexpr int kMaxRings = 16;
    int rings = 0;       // R: rings around the central patch; 0: as many as there are levels
    int vertex_step = 1; // d: samples of a tile's level per vertex along a side (1 or 2)

    // Throws ridge::Error naming the setting outside its range, or saying why `geometry`'s
    // patches cannot make the static grids (the root must be drawable as tiles:
    // (n − 1)/d ≥ 2^F).
    void validate(const PyramidGeometry& geometry) const;
};

// The tiles a turn of a globe that goes round the Earth (TerrainFrame's wrap columns over the
// finest patch's columns), 0 on any other frame. Throws ridge::Error when the grid wraps but
// its finest patches do not divide the turn, naming the patch sizes that would.
int ringsWrapTiles(const TerrainFrame& frame);

// One cell of the toroidal array: a tile of the window around the central patch.
struct RingCell {
    int tile_x = -1, tile_y = -1; // the tile (finest patch) this cell holds; −1: none yet
    int ring = 0;                 // Chebyshev distance to the central patch
    Orientation orientation = Orientation::Centre;
    bool exists = false;                      // inside the terrain
    float min_height = 0.f, max_height = 0.f; // of the tile's surface at any level it draws
};

class RingsStructure {
  public:
    RingsStructure() = default;
    // `tree` must outlive the structure. Validates `settings` against the tree's geometry.
    RingsStructure(const PatchQuadtree& tree, const RingsSettings& settings);

    // The paper's updateRings(i, j): (i, j) becomes the central patch (clamped to the
    // terrain's tiles). Incremental when it is the current centre or one of its eight
    // neighbours, a full rebuild otherwise (the first call, a jump).
    void updateRings(int i, int j);

    int rings() const { return rings_; } // R
    int window() const { return 2 * rings_ + 1; }
    int centreX() const { return centre_x_; }
    int centreY() const { return centre_y_; }
    int tilesX() const { return tiles_x_; }
    int wrapTiles() const { return wrap_tiles_; } // tiles a turn when they wrap, else 0
    // Tile column x seen from the centre: x − centre, the short way round when tiles wrap.
    int dxOf(int x) const;
    // Tile column x + dx, wrapped when tiles wrap; −1 beyond the terrain.
    int columnAt(int x, int dx) const;
    int tilesY() const { return tiles_y_; }
    int finestLevel() const { return finest_; }
    int vertexStep() const { return vertex_step_; }
    // Cells whose tile (and bounds) the last updateRings replaced.
    int cellsRefreshed() const { return refreshed_; }

    // The cell of tile (x, y) in the toroidal array; the tile must lie within the window.
    const RingCell& cell(int x, int y) const;
    // Ring of tile (x, y) around the current centre (any tile).
    int ringOf(int x, int y) const;
    Orientation orientationOf(int x, int y) const;
    // The level ring `ring` draws at, `coarser` levels coarser than designed (>= 0).
    int levelOfRing(int ring, int coarser = 0) const;
    // Whether the ring outside `ring` draws coarser (its tiles stitch outwards).
    bool outerRingCoarser(int ring, int coarser = 0) const
    {
        return levelOfRing(ring + 1, coarser) < levelOfRing(ring, coarser);
    }
    // Mesh cells a side of a tile drawn at `level`: (n − 1)/(2^(F − level)·d).
    int cellsAt(int level) const;
    // Height range of tile (x, y) drawn at any level (finest bounds widened by the largest
    // Err(P) of its drawable ancestors).
    void tileBounds(int x, int y, float& min_height, float& max_height) const;

  private:
    void assign(RingCell& c, int x, int y) const;
    RingCell& at(int x, int y);

    const PatchQuadtree* tree_ = nullptr;
    // tileBounds of every tile, computed once (shared by copies: preview's scratch).
    std::shared_ptr<const std::vector<std::array<float, 2>>> bounds_;
    int rings_ = 0, vertex_step_ = 1, finest_ = 0, tiles_x_ = 0, tiles_y_ = 0, cells_ = 0;
    int centre_x_ = 0, centre_y_ = 0;
    int centre_vx_ = 0; // centre_x_ unwrapped (moves the short way round a wrapping globe)
    int wrap_tiles_ = 0;
    bool built_ = false;
    int refreshed_ = 0;
    // window² cells, [(y mod W)·W + x mod W] for the tile's column x seen from the centre
    // (centre + dxOf: unwrapped, so the window never holds one column twice)
    std::vector<RingCell> cells_array_;
};

// A tile as one frame draws it.
struct RingTile {
    int x = 0, y = 0; // the tile (finest patch) column and row
    int ring = 0;
    int level = 0; // drawn level
    // EdgePosition bits (edgeBit): edges and corners whose heights come from level − 1,
    // from the levels of the tiles around it.
    uint8_t stitch = 0;
    // The paper's case: the tile and its eight neighbours all exist and draw their rings'
    // levels, so its stitching is kStitchTable[orientation] (Centre where the ring outside
    // is not coarser), which the vertex shader looks up; otherwise (the terrain's border, a
    // cover lowered while streaming) `stitch` is sent as it is.
    bool by_table = false;
    Orientation orientation = Orientation::Centre;
    Visibility visibility = Visibility::Inside;
};

// Scheme rings' selection: updateRings on the camera's tile, frustum culling per tile
// (RenderSettings::cull), the patches the visible tiles draw (and the coarser ones their
// stitched edges read), ranked inner rings first. When they exceed max_patches, every ring
// is drawn one level coarser until they fit (Selection::levels_coarser).
class RingsSelector final : public PatchSelector {
  public:
    RingsSelector(const PatchQuadtree& tree, const RingsSettings& settings);

    void select(const Camera& camera, const SelectionSettings& settings, Selection& out) override;
    void preview(const Camera& camera, const SelectionSettings& settings,
                 Selection& out) const override;
    void cover(const Selection& desired, const std::function<bool(PatchId)>& resident,
               ResidentCover& out) override;

    const RingsStructure& structure() const { return structure_; }
    // What the last cover() draws, visible tiles only, in tile order.
    const std::vector<RingTile>& drawnTiles() const { return drawn_; }
    // Visible tiles whose desired level the last cover() lowered (streaming).
    int lowered() const { return lowered_; }
    // Tile (x, y)'s ancestor at `level`.
    PatchId ancestorOf(int x, int y, int level) const
    {
        const int k = structure_.finestLevel() - level;
        return PatchId{level, x >> k, y >> k};
    }

  private:
    // Per tile, this frame.
    struct TileState {
        int8_t visible = 0;
        int8_t ring = 0;
        int8_t desired = 0; // level
        int8_t level = 0;   // cover's
        Visibility visibility = Visibility::Inside;
    };
    void centreOn(RingsStructure& s, const Camera& camera) const;
    void desire(const RingsStructure& s, const Camera& camera, const SelectionSettings& settings,
                std::vector<TileState>& tiles, Selection& out) const;
    void listPatches(const RingsStructure& s, const std::vector<TileState>& tiles, bool use_desired,
                     int coarser, Selection& out) const;
    uint8_t stitchOf(size_t t, const std::vector<TileState>& tiles, bool at_desired) const;
    bool atRingLevels(size_t t) const;
    int levelAt(int x, int y, const std::vector<TileState>& tiles, bool desired) const;

    const PatchQuadtree& tree_;
    RingsStructure structure_;
    std::vector<TileState> tiles_;             // tilesX·tilesY
    int coarser_ = 0;                          // this frame's levels_coarser
    mutable RingsStructure preview_structure_; // preview's scratch
    mutable std::vector<TileState> preview_tiles_;
    std::vector<RingTile> drawn_;
    Selection cover_patches_; // scratch
    int lowered_ = 0;
};

} // namespace ridge::lod
