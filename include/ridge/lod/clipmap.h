#pragma once
// Geometry clipmaps, GPU-based (Asirvatham & Hoppe), as the clipmaps thesis builds them
// (gpu-geometry-clipmaps-thesis.txt, chapter 3): the window policy of scheme `clipmaps`, plain
// C++. The footprints the levels are drawn with are lod/clipmap_footprints.h; the GL half
// (level textures, toroidal updates, shaders) is src/render/schemes/.
//
// L levels, each an n × n window (n = 2^k − 1) of one level of ridge's pyramid, nested about
// the viewer: level k (0 the coarsest … L − 1 the finest) holds the samples of pyramid level
// F − (L − 1 − k), F the archive's finest, one sample every step = 2^(L − 1 − k) finest samples.
// Levels coarser than the archive's level 0 (pyramid level < 0) are level 0 decimated, so
// that the coarsest window can always span the whole terrain.
//
// Windows are placed in finest-grid samples (integers, exact). Every window's origin lies on
// the next coarser level's grid (a multiple of 2·step), and a level sits in the hole of the
// next coarser ring — 2m of its cells, m = (n + 1)/4 — against one side or the other: the
// coarser window is the finer one's origin less (m − 1) coarse cells, rounded down to the
// coarser-still grid (the thesis's "finer levels are never exactly centred"). The one-cell
// gap on the other side is the interior trim. Only the finest window follows the viewer
// directly (rounded to the nearest even sample); every coarser one follows the finer, so a
// level shifts only when the level inside it has moved by one of its cells.
//
// A level shift moves a window by whole samples; the level's texture is addressed
// toroidally (sample i at texel i mod (n + 1)), so only the new L-shaped strip is written
// (updateRegions).
#include "ridge/pyramid/pyramid_geometry.h"

#include <cstdint>
#include <vector>

namespace ridge::lod {

struct ClipmapSettings {
    // n: 63 keeps room for the transition regions (transitionWidth) inside each ring; 1023 is
    // the largest whose m × m blocks fit 16-bit indices (the thesis's limit).
    static constexpr int kMinN = 63, kMaxN = 1023;
    static constexpr int kMaxLevels = 24;
    int n = 255; // samples a side of every level window: 2^k − 1
    // L; 0: from the finest level to the first whose window spans the terrain, and to the
    // archive's level 0 at least (the root, always resident: the coarsest level never waits)
    int levels = 0;

    int m() const { return (n + 1) / 4; }
    // Throws ridge::Error naming the setting ("n", "levels") that is out of range.
    void validate() const;
};

// L for `settings` over `geometry`: settings.levels, or (0) as many as needed for the
// coarsest window to hold the whole terrain wherever it is centred on it, and at least the
// archive's levels (the coarsest then reads the root).
int clipmapLevelCount(const ClipmapSettings& settings, const PyramidGeometry& geometry);

// floor(a / b) for b > 0, whatever a's sign (windows and their samples reach west and north of
// the terrain, to negative coordinates).
int64_t floorDiv(int64_t a, int64_t b);

// The width w of a level's transition region, in its cells (Losasso & Hoppe: n/10), and the
// blend parameter α at a point `distance` cells (Chebyshev, per axis) from the viewer:
// α = clamp((distance − ((n − 1)/2 − w − 2))/w, 0, 1). It is 1 on the window's perimeter (the
// viewer is within 1.5 cells of a window's centre, see ClipmapWindows) and 0 on the inner
// border of its ring (at most m + 2 cells out), so a level meets the coarser one with the
// coarser one's surface and the finer one with its own.
int transitionWidth(int n);
double transitionAlpha(int n, double distance);

// A rectangle of one level's samples [x0, x1) × [y0, y1), in that level's sample coordinates.
struct LevelRect {
    int64_t x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    int64_t area() const { return (x1 - x0) * (y1 - y0); }
};

struct ClipmapLevel {
    int pyramid_level = 0; // the archive level it holds; < 0: level 0 decimated
    int64_t step = 1;      // finest samples between its samples: 2^(L − 1 − k)
    // Finest column and row of the window's sample (0, 0): a multiple of 2·step.
    int64_t origin_x = 0, origin_y = 0;
    // Where the next finer level sits in this level's hole, per axis: 0 against the low side
    // (the interior trim then runs along the high side), 1 against the high side.
    int finer_x = 0, finer_y = 0;

    // The window in this level's sample coordinates.
    LevelRect window(int n) const
    {
        return {origin_x / step, origin_y / step, origin_x / step + n, origin_y / step + n};
    }
};

class ClipmapWindows {
  public:
    // L levels of n over `geometry` (settings validated; levels resolved by
    // clipmapLevelCount).
    ClipmapWindows(const PyramidGeometry& geometry, const ClipmapSettings& settings);

    int n() const { return n_; }
    int m() const { return (n_ + 1) / 4; }
    int levelCount() const { return int(levels_.size()); }
    const ClipmapLevel& level(int k) const { return levels_[size_t(k)]; }

    // Places every window about the viewer at finest column, row `centre` (the camera's
    // projection onto the terrain's basis; clamp it to the terrain first). Returns how many
    // levels shifted (a level shifts when its origin changes; the first placement shifts
    // them all).
    int place(double centre_x, double centre_y);
    bool placed() const { return placed_; }
    // The samples level k must newly hold after the last place(): nothing when it did not
    // shift, the whole window after a move of n samples or more (or the first placement),
    // else the L-shaped strip as at most two disjoint rectangles.
    const std::vector<LevelRect>& updateRegions(int k) const { return updates_[size_t(k)]; }

  private:
    int n_ = 0;
    int64_t finest_ = 0; // the archive's finest level F
    bool placed_ = false;
    std::vector<ClipmapLevel> levels_;
    std::vector<std::vector<LevelRect>> updates_;
};

// Level deactivation (§3.5.4, after Clasen & Hege): the finest level worth drawing for a
// viewer `height` metres above the ground, the finer ones skipped and the hole filled by it.
// A level is drawn when its triangles are at least two screen pixels under the viewer:
// spacing ≥ 2·s, s = h·tan(fov/#p) the pixel's footprint there. `spacing` is metres per
// finest sample (the larger axis: cells near a pole are thin, not small). The coarsest level
// is always drawn. (Asirvatham & Hoppe's
// rule — a window narrower than 2.5 h is skipped, §2.3.1 — assumes a 90° field of view; with a
// narrow one it drops levels that fill the view, so it is not used.)
int finestDrawnLevel(const ClipmapWindows& windows, double spacing, double height,
                     double fov_y_radians, int viewport_height_px);

} // namespace ridge::lod
