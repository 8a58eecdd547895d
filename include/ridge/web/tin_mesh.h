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
// Cost: O(V log V) for the queue and flips, plus rescanning the samples under the triangles
// each insertion changes (on rough terrain some 15-25 times the grid in all), plus one final
// pass over the grid that measures the error reported. A 257² tile of rough terrain takes
// about 4, 7 and 16 ms at 10, 5 and 2 m (300 to 4900 vertices) on a 2 GHz-class core.
// Memory: O(V) besides the caller's grid, which is read in place.
#include <cstdint>
#include <span>
#include <vector>

namespace ridge::web {

// The grid's frame: column c runs east, row r runs SOUTH (row 0 is the northern edge, as in a
// raster). Triangles are counter-clockwise in (x, y) = (c, −r): counter-clockwise seen from
// above with north up. (Drawn as a raster, with r growing downwards, they look clockwise.)
struct Tin {
    // Per vertex: its grid column and row (0..width−1, 0..height−1) and the grid's height
    // there, bit for bit. Every vertex is a distinct grid sample; the four corners are always
    // vertices (0..3: north-west, south-west, south-east, north-east), then the border
    // vertices, then the interior ones in the order they were inserted.
    std::vector<uint32_t> columns, rows;
    std::vector<float> heights;
    // Three vertex indices per triangle, counter-clockwise in (column, −row) (see above).
    // Every triangle has positive area, and together they tile the rectangle
    // [0, width−1] × [0, height−1] exactly, with no T-junction.
    std::vector<uint32_t> triangles;
    // The largest |grid sample − mesh| over every sample of the grid, metres (<= the
    // max_error asked). The mesh at a sample is the planar interpolation of the triangle
    // containing it (on an edge, the linear interpolation along that edge).
    double max_error = 0.0;
};

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
