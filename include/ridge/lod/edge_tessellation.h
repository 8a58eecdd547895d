#pragma once
// Fine-grain LOD: tessellation factors of a tessellation block's edges
// ("Fine-Grain Level of Detail Selection", Yusov & Shevtsov 2011, §5).
//
// For an edge with centre e_c and edge errors Λ_e^(d) = max of Λ^(d) of the blocks sharing
// it, where Λ^(d) = λ^(d) + Err(P), the segment e_c ± Λ_e^(d)/2 · e_z is projected to the
// screen; the edge is simplified by the largest 2^d whose projected length stays below ε:
//
//   d = arg max_d proj(e_c^(d)−, e_c^(d)+) < ε       (d = 0: full resolution)
//
// and its tessellation factor is b / 2^d for a block of b cells. The block interior takes the
// minimum of its four edge factors. Edges shared by two blocks see the same inputs in both, so
// both pick the same factor: no cracks inside a patch.
//
// shaders/edge_tessellation.glsl is the GPU twin of this file; tests/lod checks that both
// pick the same d for the same inputs.
#include "ridge/lod/camera.h"

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

namespace ridge::lod {

inline constexpr int kMaxBlockLevels = 4; // Λ^(d), d = 1..4, fits one vec4 per block

// Edge errors Λ_e^(d) of an edge between blocks with errors `a` and `b` (d = 1..levels).
struct EdgeErrors {
    float lambda[kMaxBlockLevels] = {};
};
EdgeErrors sharedEdgeErrors(const EdgeErrors& a, const EdgeErrors& b, int levels);

// Projected length in pixels of the vertical segment of `length` metres centred at
// `centre_rel` (camera-relative); +inf when an end is behind the near plane.
double projectedVerticalSegment(const glm::dmat4& view_projection, Viewport viewport,
                                glm::dvec3 centre_rel, double length);

// The paper's d for one edge, in [0, levels].
int edgeSimplification(const glm::dmat4& view_projection, Viewport viewport, glm::dvec3 centre_rel,
                       const EdgeErrors& errors, int levels, double epsilon_px);

// b / 2^d.
inline int tessellationFactor(int block_cells, int d)
{
    return block_cells >> d;
}

} // namespace ridge::lod
