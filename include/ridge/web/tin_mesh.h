#pragma once
// A triangulated irregular network (TIN) of a height grid that keeps every sample within a
// vertical bound: the mesh body of a Cesium quantized-mesh tile.
//
// This work is based on: Garland, Heckbert 1995, "Fast Polygonal Approximation of Terrains and
// Height Fields" (CMU-CS-95-181), the greedy-insertion Delaunay algorithm that mapbox/delatin
// also follows. Starting from a coarse Delaunay triangulation, the sample farthest (vertically)
// from the mesh is inserted, the triangulation made Delaunay again by edge flips, and the
// candidates of the changed triangles recomputed, until no sample is farther than the bound.
//
// The border rule. Neighbouring tiles sample their shared border line identically, and must
// put identical vertices on it or the globe shows cracks. So each of the four border lines
// (north row, south row, west column, east column) is first simplified alone, by the 1-D form
// of the same greedy insertion over that line's samples only (starting from its two corners,
// ties to the lowest index along the line, the line read west to east or north to south); its
// chosen samples become the only vertices on that border, and border edges stay hull edges
// (never flipped), so a border's vertices depend on that border's samples alone and its
// samples' error is the 1-D error. Interior samples are the only candidates afterwards.
//
// The rectilinear form. A web tile's edges fall between the archive's samples, so a tile
// grid resampled at uniform positions inside the tile loses the archive's own samples: its
// mesh keeps the bound against the resampled grid, not against the data (on Himalaya data
// the real samples lay up to 79.7 m from a mesh bounded at 18.8 m). So the grid may be
// rectilinear: its interior lines are the archive's own sample columns and rows, its first
// and last the tile's edges, and the mesh's bound then holds at every real data sample. Its
// lines are at arbitrary strictly increasing integer positions (xs for the columns, ys for
// the rows, up to 2^24), and every geometric step (Delaunay, orientation, interpolation, the
// error, the 1-D border pass along a border's positions) works in those positions, exactly:
// orientations fit int64, in-circle determinants __int128, and the barycentric weights stay
// exact integers in doubles. The uniform form is the rectilinear one with xs[c] = c,
// ys[r] = r. A border's vertices depend on that border's samples and positions alone.
//
// Cost: O(V log V) for the queue and flips, plus rescanning the samples under the triangles
// each insertion changes (on rough terrain some 15-25 times the grid in all), plus one final
// pass over the grid that measures the error reported. A 257² tile of rough terrain takes
// about 4.5, 8 and 17 ms at 10, 5 and 2 m (300 to 4900 vertices) on a 2 GHz-class core, the
// same uniform or rectilinear with uneven edge gaps (the scan steps over the grid's usual
// spacing by adding; on grids with no usual spacing it recomputes the weights at every
// sample, which costs more).
// Memory: O(V) besides the caller's grid, which is read in place.
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace ridge::web {

// The grid's frame: column c runs east, row r runs SOUTH (row 0 is the northern edge, as in a
// raster). Column c lies at x = xs[c], row r at y = ys[r] (the uniform form: x = c, y = r).
// Triangles are counter-clockwise in (x, −y): counter-clockwise seen from above with north
// up. (Drawn as a raster, with y growing downwards, they look clockwise.)
struct Tin {
    // Per vertex: its grid column and row (indices 0..width−1, 0..height−1, not positions:
    // the caller maps them through xs and ys) and the grid's height there, bit for bit. Every
    // vertex is a distinct grid sample; the four corners are always vertices (0..3: north-west,
    // south-west, south-east, north-east), then the border vertices, then the interior ones in the
    // order they were inserted.
    std::vector<uint32_t> columns, rows;
    std::vector<float> heights;
    // Three vertex indices per triangle, counter-clockwise in (x, −y) (see above). Every
    // triangle has positive area in (x, y), and together they tile the rectangle
    // [xs.front(), xs.back()] × [ys.front(), ys.back()] exactly, with no T-junction.
    std::vector<uint32_t> triangles;
    // The largest |grid sample − mesh| over every sample of the grid, metres (<= the
    // max_error asked). The mesh at a sample is the planar interpolation, in (x, y), of the
    // triangle containing it (on an edge, the linear interpolation along that edge).
    double max_error = 0.0;
};

// The TIN of a rectilinear grid of heights: column c lies at x = xs[c], row r at y = ys[r]
// (row 0 north, y growing SOUTH like the row index), both strictly increasing integers in
// [0, 2^24]; the mesh's geometry (Delaunay, orientation, interpolation, error) is in these
// coordinates. Heights are row-major (row r, column c at r·xs.size() + c, metres, all
// finite); otherwise as the uniform form below, which is this one with xs[c] = c, ys[r] = r.
//
// `border_error`, when given, is the bound the four border lines are simplified within
// instead of max_error: neighbouring tiles whose interiors get different bounds (each its
// own budget) must still choose the same vertices on their shared border, so they pass the
// same border bound. The max_error reported covers both.
//
// Throws ridge::Error naming the parameter when xs.size() or ys.size() is outside
// [2, 65536], a position is outside [0, 2^24] or not greater than the one before it,
// heights.size() != xs.size()·ys.size(), a height is not finite, or max_error (or
// border_error) is negative or not finite.
Tin buildTin(std::span<const float> heights, std::span<const int32_t> xs,
             std::span<const int32_t> ys, double max_error,
             std::optional<double> border_error = std::nullopt);

// The TIN of a width × height grid of heights (row-major: row r, column c at r·width + c,
// metres, all finite) whose every sample lies within max_error (metres, >= 0; 0 keeps every
// sample not exactly on the plane of its triangle) of the mesh. Deterministic: equal inputs
// give equal output, and among equally bad samples the lowest row-major index goes first.
//
// Throws ridge::Error naming the parameter when width or height is outside [2, 65536],
// heights.size() != width·height, a height is not finite, or max_error is negative or not
// finite.
Tin buildTin(std::span<const float> heights, int width, int height, double max_error);

} // namespace ridge::web
