#pragma once
// Scheme clipmaps' residency policy (lod::PatchSelector), plain C++: which patches the level
// windows (lod/clipmap.h) need resident, and which samples of which level textures are still
// to be written from them.
//
// The level textures are the clipmap's own copy of the terrain: once a patch's samples are
// written into every window that holds them, the patch need not stay resident. So the policy
// is a list of pending writes per level — (patch, rectangle of the level's samples) — that a
// level shift appends to (its L-shaped strip, split by the patches under it) and that the
// GL half drains each frame for the patches that are resident (takeWrites), coarse levels
// first. A level is drawn only when it has nothing pending, and only if every coarser level
// is drawn too (a level blends into the next coarser one at its perimeter): while a strip is
// not resident that level and the finer ones are skipped and the coarser level shows through.
// The render thread never waits: what is missing is requested, coarse to fine, and drawn when
// it has arrived.
//
// select() wants the patches of the pending writes of the levels level deactivation keeps
// (finestWanted); preview() — the planner's prefetch, for a camera extrapolated along the
// motion — wants what the windows would newly need there, so the strips of coming shifts are
// loaded before the windows reach them.
//
// Levels coarser than the archive's level 0 read its root patch, decimated. Window samples
// beyond the terrain take the nearest patch's edge samples (the clip stage cuts the surface
// at the terrain's border; what lies beyond only shapes the cut).
//
// On a globe whose columns go round the Earth (GeodeticGrid::wrap_columns, the turn) the
// windows do not stop at the antimeridian: their columns run on, unwrapped, and a level's
// sample i is read at i mod (its samples a turn), so crossing the seam is a level shift like
// any other. The window centre follows the camera continuously (the copy of its column
// nearest the last centre). Every level's cells must then divide the turn, and on the
// ellipsoid a pole on the last row must lie on every level's grid.
#include "ridge/lod/clipmap.h"
#include "ridge/lod/patch_selector.h"

#include <glm/vec2.hpp>

#include <functional>
#include <vector>

namespace ridge::lod {

// Samples `rect` of level `level`'s window, to be written from `patch`: level sample (i, j)
// is read where its sample (i − wrap_shift, j) lies (wrap_shift a whole number of turns on a
// wrapping globe, else 0).
struct ClipmapWrite {
    int level = 0;
    PatchId patch;
    LevelRect rect;
    int64_t wrap_shift = 0;
};

// Where the levels end on a globe whose columns go round the Earth. A level at least a turn
// wide would cover the globe twice over, so the wide levels are cut to one turn [west,
// west + T): `west` on the grid of every level cut, the turn holding the narrower levels'
// windows and inside the finest wide level's, so that both ends — one meridian — are drawn by
// the same level with the same samples. Levels coarser than `coarsest` are not drawn: within
// the turn, the finest wide level (or the first coarser one that reaches both ends of the
// rows) covers everything they would.
struct ClipmapTurnCut {
    bool cut = false; // false: no level is a turn wide (or the grid does not wrap)
    int64_t west = 0; // finest column
    int coarsest = 0; // the coarsest level drawn
};

// Throws ridge::Error when `levels` windows of `n` cannot lie on `frame`'s globe: on a grid
// that wraps, the coarsest cells must divide the turn and the coarsest window span it; with
// a pole on the last row, the cells must divide its distance from row 0. Names the levels or
// the n that would. Nothing to check on the plane.
void checkClipmapGlobe(const TerrainFrame& frame, int n, int levels);

class ClipmapSelector final : public PatchSelector {
  public:
    // `tree` must outlive the selector. Throws ridge::Error for settings out of range, and on a
    // wrapping globe whose turn the coarsest level's cells do not divide, or with a pole row
    // between them (naming the levels that would).
    ClipmapSelector(const PatchQuadtree& tree, const ClipmapSettings& settings);

    void select(const Camera& camera, const SelectionSettings& settings, Selection& out) override;
    void preview(const Camera& camera, const SelectionSettings& settings,
                 Selection& out) const override;
    void cover(const Selection& desired, const std::function<bool(PatchId)>& resident,
               ResidentCover& out) override;

    const ClipmapWindows& windows() const { return windows_; }
    // The finest column and row the windows were last placed about: the camera's projection
    // onto the terrain's basis (TerrainFrame::gridOf), clamped to the terrain.
    glm::dvec2 centre() const { return centre_; }
    // Levels that shifted in the last select().
    int shifts() const { return shifts_; }
    // The finest level level deactivation keeps for the last select()'s camera.
    int finestWanted() const { return finest_wanted_; }
    // The finest level that may be drawn now: levels 0..k all complete, k ≤ finestWanted;
    // −1 when the coarsest is not.
    int finestDrawn() const;
    bool complete(int level) const { return pending_[size_t(level)].empty(); }
    size_t pendingWrites() const;

    // Moves the pending writes whose patch is resident into `out` (coarse levels first): the
    // caller writes them now.
    void takeWrites(const std::function<bool(PatchId)>& resident, std::vector<ClipmapWrite>& out);

    // The patch level k's sample (i, j) is read from (edge samples beyond the terrain; on a
    // wrapping globe column i wraps).
    PatchId patchOf(int level, int64_t i, int64_t j) const;
    // Finest columns a turn of the globe when the windows wrap, else 0.
    int64_t turn() const { return turn_; }
    // The cut to one turn when levels ..finest are drawn (finest ≥ 0).
    ClipmapTurnCut turnCut(int finest) const;
    // How many of the root's samples apart level k's samples are (1 for archive levels).
    int64_t decimation(int level) const;

  private:
    // The window centre for `camera`, clamped to the terrain, and the viewer's distance to
    // the ground there (metres: height above the highest sample, and how far off the
    // terrain it is), for level deactivation.
    glm::dvec2 centreOf(const Camera& camera, double exaggeration, double& distance) const;
    int wantedFinest(const Camera& camera, double distance) const;
    // `rect` of level k split by the turns it spans (on a wrapping globe) and the patches it
    // reads.
    void splitByPatch(int level, const LevelRect& rect, std::vector<ClipmapWrite>& out) const;
    // `rect` (within one turn) split by the patches it reads, shifted back by `shift`.
    void splitWithinTurn(int level, const LevelRect& rect, int64_t shift,
                         std::vector<ClipmapWrite>& out) const;
    // Level k's samples a turn (turn_ > 0).
    int64_t samplesPerTurn(int level) const { return turn_ / windows_.level(level).step; }
    // Appends to `out` the patches of `writes` not in it yet, ranked coarse levels first.
    void want(const std::vector<ClipmapWrite>& writes, size_t max_patches, Selection& out) const;

    const PatchQuadtree& tree_;
    ClipmapWindows windows_;
    int64_t turn_ = 0;
    std::vector<std::vector<ClipmapWrite>> pending_; // per level
    glm::dvec2 centre_{0.0};
    int shifts_ = 0;
    int finest_wanted_ = 0;
};

} // namespace ridge::lod
