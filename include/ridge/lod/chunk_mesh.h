#pragma once
// Ulrich's chunks ("Rendering massive terrains using chunked level of detail", 2000), the
// baseline the hardware-tessellation paper measures itself against: each patch drawn as one
// precomputed mesh, simplified to a vertical tolerance, with a skirt around it.
//
// The mesh is a 4-8 mesh (longest-edge bisection of right triangles) over the patch's
// (2^k+1)² samples. A triangle is split at its hypotenuse midpoint m when E(m) > τ, where
// E(m) is the worst vertical deviation of a sample from the plane of either triangle m would
// split, raised to the E of every vertex below m (Lindstrom and Pascucci's nested errors).
// Because both triangles on a hypotenuse consult the same E(m), and E never grows down the
// hierarchy, the mesh has no T-junction; because E(m) bounds the triangle's own deviation,
// every sample lies within τ of the mesh.
#include <cstdint>
#include <functional>
#include <vector>

namespace ridge::lod {

struct ChunkMesh {
    // Vertex ids as shaders/chunk.vert reads them: y·n + x for sample (x, y), n² + k for the
    // foot of the k-th border sample in ring order (north row west to east, east column,
    // south row east to west, west column). Triangles are counter-clockwise in (x, y), the
    // orientation of the full-grid mesh; skirt triangles start and end with a foot.
    std::vector<uint32_t> indices;
    uint32_t surface_indices = 0; // [0, surface_indices) are the surface, the rest the skirt
    double max_deviation = 0.0;   // worst |sample − mesh| over the valid samples, in codes
};

// The chunk of an n×n patch of `codes` (n = 2^k + 1, row-major) simplified to `tolerance`
// (codes, >= 0; 0 removes only samples that lie exactly on their triangle's plane).
//
// A patch reaching past the terrain's east or south border is drawn up to the border, which
// may fall inside its last cells; it takes samples only for x <= valid_x, y <= valid_y
// (PyramidGeometry::coveredCellsX/Y: up to the first sample at or beyond the border, an
// edge-extended one when the level's samples miss it). Only those count towards the error,
// and no triangle crosses those lines, so nothing drawn rests on unmeasured padding. The
// renderer's clipping shader then cuts at the border itself, computing each cut point from its
// edge's endpoints alone: the mesh has no T-junction, so clipped chunks stay watertight.
//
// On a globe a flat triangle also sags below the curved surface, by more the larger it is:
// `sag(cells)`, when given, is that sag (codes) for a triangle within a square of `cells`
// cells, non-decreasing, and it counts towards τ with the heights' deviation. A chunk then
// never joins samples a quarter of the Earth apart in one flat triangle (whose chord would lie
// thousands of kilometres inside it, or be a degenerate line through the poles).
// max_deviation stays the heights' alone (the skirts add the patch's sag themselves).
using ChunkSag = std::function<double(int cells)>;
ChunkMesh buildChunkMesh(const uint16_t* codes, int n, double tolerance);
ChunkMesh buildChunkMesh(const uint16_t* codes, int n, double tolerance, int valid_x, int valid_y,
                         const ChunkSag& sag = {});

} // namespace ridge::lod
