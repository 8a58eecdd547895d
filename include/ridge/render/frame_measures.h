#pragma once
// What a rendered frame shows, measured (plain C++, no GL): the figures every benchmark run
// reports beside its frame times, and the conformance suite asserts.
//
//   * hole pixels: background showing through inside the terrain's footprint;
//   * popping: the largest screen-space displacement of the surface that LOD changes alone
//     cause — the same camera drawn with the previous frame's LOD state and with this one's
//     (TerrainRenderer::capture's lod_camera) — in pixels. No peer publishes it.
#include "ridge/lod/camera.h"
#include "ridge/lod/terrain_frame.h"
#include "ridge/render/terrain_renderer.h"

#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace ridge::render {

struct HoleReport {
    size_t footprint_pixels = 0; // pixels whose ray must hit the terrain
    size_t hole_pixels = 0;      // of those, background
    int first_x = -1, first_y = -1;
};

// `background[y·width + x]` is nonzero where the frame shows no terrain (row 0 at the top),
// e.g. depth == 0 under the renderer's reverse-Z. A pixel counts as inside the footprint when
// its ray crosses the whole slab of heights [min_height, max_height] (terrain frame, metres)
// downwards inside the terrain's extent, less one sample at each border: such a ray must hit
// the continuous surface. Rays that graze the slab or leave the extent are not judged (no
// false holes; a hole seen only at a grazing angle is missed). On a globe frame: from outside
// the sphere that holds all the terrain, a ray that meets the sphere inside all of it, both
// points where the grid covers the Earth.
// `limb_px` (globe): rays passing within this many pixels of the inner sphere's silhouette are
// not judged — the drawn globe's edge may fall short of the true one by what ε allows there
// (twice the ε met is safe).
// `surface_under_camera` (plane frames): the drawn surface's height under the camera
// (surfaceHeightUnder of the frame's own capture, TerrainRenderer::lastFrameSurface), NaN when
// unknown. A camera inside the slab — a low fly-over — whose position is inside the extent
// and at least 1 m above that surface judges its downward rays from itself: a ray that leaves
// the slab's bottom inside the extent started above the drawn surface and ends below it, so
// it crosses it (the extent is convex, the drawn surface closed by skirts). Rays that rise,
// or leave the extent first, are not judged (a ridge may rise in front of a low camera, or
// not).
HoleReport countHolePixels(const std::vector<uint8_t>& background, const lod::Camera& camera,
                           const lod::TerrainFrame& frame, double min_height, double max_height,
                           double limb_px = 4.0,
                           double surface_under_camera = std::numeric_limits<double>::quiet_NaN());

// The height of the highest triangle of a captured surface (skirts excluded) over the point
// (x, y) of a plane terrain frame, metres; NaN where none covers it. Throws ridge::Error on
// an ellipsoid frame.
double surfaceHeightUnder(const CapturedSurface& surface, const lod::TerrainFrame& frame, double x,
                          double y);

// The height of a captured surface (skirts excluded) at every finest sample it covers,
// terrain frame metres, NaN elsewhere, over the window of finest samples its triangles span
// (a view of a continent covers a fraction of the grid).
struct SampleHeights {
    int x0 = 0, y0 = 0, width = 0, height = 0; // finest columns x0.., rows y0..
    std::vector<float> z;                      // width × height, row-major
    float at(int column, int row) const;       // NaN outside the window or uncovered
};
SampleHeights surfaceHeightsAtSamples(const CapturedSurface& surface,
                                      const lod::TerrainFrame& frame);

struct PoppingReport {
    size_t samples = 0;  // finest samples in view covered by both surfaces
    double max_px = 0.0; // largest projected vertical displacement, pixels
    double max_metres = 0.0;
    // Every this many samples along each axis were compared: 1 for measurePopping; the GPU
    // measure (TerrainRenderer::endPopping) samples a window larger than its texture limit.
    int sample_stride = 1;
};

// The displacement between two surfaces (surfaceHeightsAtSamples of the same frame drawn
// with two LOD states) seen from `camera`: per sample in view, the distance in pixels
// between the projections of its two heights.
PoppingReport measurePopping(const SampleHeights& before, const SampleHeights& after,
                             const lod::TerrainFrame& frame, const lod::Camera& camera);

} // namespace ridge::render
