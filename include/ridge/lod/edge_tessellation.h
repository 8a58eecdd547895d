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
// That rule (TessellationRule::Paper) misses ε: Λ is projected at the edge centre while the
// edge's near end projects larger, and an interior nearer the camera than its edges gets the
// coarsest of them. ridge's default, TessellationRule::Conservative, tests each edge with
// 2λ_e^(d) + Err(P) at its endpoints, centre sample and point nearest the camera and takes the
// most demanding d (still from the edge's own samples and the shared Λ_e, so shared edges
// agree; a sample under a transition triangle between a coarse edge and a finer interior is
// within 2λ^(d) of the decoded surface, see shaders/edge_tessellation.glsl, and the decoded
// surface within Err(P) of the source), and gives the interior its
// own test with the block's Λ^(d) at its corners, centre sample and the nearest point of its
// footprint box, refined to at least its finest edge.
//
// shaders/edge_tessellation.glsl is the GPU twin of this file; tests/render's twin test
// checks that both pick the same d for the same inputs.
#include "ridge/lod/camera.h"

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

namespace ridge::lod {

inline constexpr int kMaxBlockLevels = 4; // Λ^(d), d = 1..4, fits one vec4 per block

// The fine-LOD rule; the values are the shaders' RIDGE_TESSELLATION_RULE (one program each).
enum class TessellationRule {
    Conservative = 0, // ε at every edge's and interior's most demanding point (the default)
    Paper = 1,        // §5 as published: edge centres, interior = min of edge factors
};

// Edge errors Λ_e^(d) = λ_e^(d) + Err(P) of an edge between blocks with errors `a` and `b`
// (d = 1..levels), and the Err(P) they include (both blocks are of one patch).
struct EdgeErrors {
    float lambda[kMaxBlockLevels] = {};
    float patch_error = 0.f; // Err(P), 0 ≤ Err(P) ≤ lambda[d]
};
EdgeErrors sharedEdgeErrors(const EdgeErrors& a, const EdgeErrors& b, int levels);

// Projected length in pixels of the vertical segment of `length` metres centred at
// `centre_rel` (camera-relative); +inf when an end is behind the near plane.
double projectedVerticalSegment(const glm::dmat4& view_projection, Viewport viewport,
                                glm::dvec3 centre_rel, double length);

// The paper's d for one edge, in [0, levels].
int edgeSimplification(const glm::dmat4& view_projection, Viewport viewport, glm::dvec3 centre_rel,
                       const EdgeErrors& errors, int levels, double epsilon_px);

// The point of segment [a, b] nearest the camera (the origin of camera-relative positions).
glm::dvec3 nearestPointOfSegment(glm::dvec3 a, glm::dvec3 b);

// d of the edge from `a` to `b` (camera-relative) with centre sample `centre` under `rule`:
// Paper: edgeSimplification at the centre; Conservative: the least d, with 2Λ_e − Err(P), of
// the endpoints, the centre and nearestPointOfSegment(a, b).
int edgeSimplification(const glm::dmat4& view_projection, Viewport viewport, glm::dvec3 a,
                       glm::dvec3 centre, glm::dvec3 b, const EdgeErrors& errors, int levels,
                       double epsilon_px, TessellationRule rule);

// The conservative rule's d of a block's interior with the block's own Λ^(d): the least d of
// its four corners, its centre sample and the point of its footprint box [lo, hi] nearest the
// camera.
int interiorSimplification(const glm::dmat4& view_projection, Viewport viewport,
                           const glm::dvec3 (&corners)[4], glm::dvec3 centre, glm::dvec3 box_lo,
                           glm::dvec3 box_hi, const EdgeErrors& own, int levels, double epsilon_px);

// The interior tessellation factor of a block with edge factors `edge_factors` under `rule`:
// Paper: their minimum; Conservative: b / 2^interior_d, at least their maximum.
int interiorFactor(TessellationRule rule, int block_cells, const int (&edge_factors)[4],
                   int interior_d);

// b / 2^d.
inline int tessellationFactor(int block_cells, int d)
{
    return block_cells >> d;
}

} // namespace ridge::lod
