#pragma once
// Checks on triangles captured from the tessellation renderer with transform feedback: the
// properties the renderer promises, measured on what the GPU actually produced.
#include "ridge/lod/camera.h"
#include "ridge/lod/terrain_frame.h"
#include "ridge/render/terrain_renderer.h"

#include <string>
#include <vector>

namespace ridge::test {

struct WatertightReport {
    size_t triangles = 0;
    size_t skirt_triangles = 0;
    size_t open_edges = 0;      // edges used once that are neither a skirt's foot nor on the
                                // terrain's outer border (x = 0, W − 1; y = 0, H − 1)
    size_t overused_edges = 0;  // edges used more than twice
    size_t seams_checked = 0;   // positions along patch seams where coverage was tested
    size_t uncovered_seams = 0; // positions where the higher side's skirt misses the lower
    std::string first_problem;
};

// Per patch: every edge is shared by exactly two triangles with bit-identical endpoints,
// except the skirts' feet and edges on the terrain's outer border. Across patches: along each
// seam between adjacent patches, the higher surface's skirt reaches down to the lower surface
// (a vertical gap is covered).
WatertightReport checkWatertight(const render::CapturedSurface& s, const lod::TerrainFrame& frame);

struct StitchedReport {
    size_t triangles = 0;
    size_t degenerate = 0;     // triangles with two bit-identical corners (not rasterised)
    size_t open_edges = 0;     // edges of the whole surface used once, off the outer border
    size_t overused_edges = 0; // edges used more than twice
    size_t walls = 0;          // triangles of the walls under the clipped border
    std::string first_problem;
};

// For schemes without skirts (stitched seams): over the whole captured surface, across every
// piece, every edge is shared by exactly two triangles with bit-identical endpoints, except
// on the terrain's outer border and the walls' feet. Degenerate triangles (two identical
// corners: a stitched odd vertex moved onto its even neighbour) cover nothing, as the
// rasteriser drops them, and are left out.
StitchedReport checkStitchedWatertight(const render::CapturedSurface& s,
                                       const lod::TerrainFrame& frame);

// The seams of `camera`'s frame checked as `settings.scheme` promises them (SchemePromises::
// seams): skirts per patch and across seams (checkWatertight), or stitching across every piece
// (checkStitchedWatertight, drawn without frustum culling: the edge of what the frustum keeps
// would be open). Block culling is turned off: culled blocks open edges nobody sees.
struct SeamReport {
    bool stitched = false;
    size_t triangles = 0;
    size_t degenerate = 0; // stitched only
    size_t problems = 0;   // open, overused and (skirts) uncovered seam positions
    std::string first_problem;
};
SeamReport checkSeamsAsPromised(render::TerrainRenderer& renderer, const lod::Camera& camera,
                                render::RenderSettings settings, const lod::TerrainFrame& frame);

struct ScreenErrorReport {
    size_t samples = 0;      // full-resolution samples in view that were compared
    double max_px = 0.0;     // largest projected vertical deviation, pixels
    double max_metres = 0.0; // largest vertical deviation, metres
    double p99_px = 0.0;     // 99th percentile of the projected deviation, pixels
    size_t uncovered = 0;    // finest samples in view with no captured surface triangle
                             // above them (a strip the surface stops short of, a hole)
    size_t overlapped = 0;   // samples strictly inside two or more surface triangles (a
                             // surface drawn twice over: a level over another, a turn twice)
};

// Projected vertical deviation of every full-resolution sample in view from the captured LOD
// surface. `finest` holds width x height heights in metres (row-major, terrain rows).
ScreenErrorReport measureScreenSpaceError(const render::CapturedSurface& s,
                                          const lod::TerrainFrame& frame,
                                          const std::vector<float>& finest,
                                          const lod::Camera& camera);

} // namespace ridge::test
