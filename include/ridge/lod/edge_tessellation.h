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
// coarsest of them. ridge's default, TessellationRule::Conservative, meets ε at every sample:
//
// * Each edge is tested with 2λ_e^(d) + Err(P) at its endpoints, centre sample and point
//   nearest the camera, taking the most demanding d (still from the edge's own samples and
//   the shared Λ_e, so shared edges agree).
// * The interior takes its own test, the block's Λ^(d) at its corners, centre sample and the
//   nearest point of its footprint box: d_I. When no edge is finer than that, the interior is
//   drawn at d_I. When one is, the interior is drawn at max(d_T, finest edge's d), where d_T
//   is the same test with 2λ^(d) + Err(P) (interiorFactor).
//
// Why 2λ: the tessellator's transition triangles between an edge and an interior of
// different d are not in the T^(c) family λ^(c) bounds (c the coarser of the two). Their
// coarse-side vertices are T^(c) vertices and their fine-side ones samples within λ^(c) of it,
// so a decoded sample under one is within 2λ^(c) of it, and the source within Err(P) more.
// A coarser edge is covered by the edge's own 2λ test, a finer edge by the interior's d_T; a
// region where edge and interior agree is a regular grid, within Λ^(d). Testing the interior
// with 2λ only where it has a finer edge (instead of making it as fine as that edge) gives
// 1.65× the paper rule's triangles on the renderer test's cameras instead of 1.90×; the
// transition strips are what keeps it from the paper's count (docs/PERF.md).
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
// Paper: edgeSimplification at the centre; Conservative: the least d, with
// transitionErrors(errors), of the endpoints, the centre and nearestPointOfSegment(a, b).
int edgeSimplification(const glm::dmat4& view_projection, Viewport viewport, glm::dvec3 a,
                       glm::dvec3 centre, glm::dvec3 b, const EdgeErrors& errors, int levels,
                       double epsilon_px, TessellationRule rule);

// The conservative rule's d of a block's interior with the block's own Λ^(d): the least d of
// its four corners, its centre sample and the point of its footprint box [lo, hi] nearest the
// camera.
int interiorSimplification(const glm::dmat4& view_projection, Viewport viewport,
                           const glm::dvec3 (&corners)[4], glm::dvec3 centre, glm::dvec3 box_lo,
                           glm::dvec3 box_hi, const EdgeErrors& own, int levels, double epsilon_px);

// 2λ^(d) + Err(P) = 2Λ^(d) − Err(P) of `errors` (Λ^(d) = λ^(d) + Err(P)): what bounds a
// transition triangle whose coarser side is at d.
EdgeErrors transitionErrors(const EdgeErrors& errors);

// The interior tessellation factor of a block with edge factors `edge_factors` under `rule`:
// Paper: their minimum; Conservative: b / 2^interior_d when no edge is finer, else
// min(b / 2^transition_d, the finest edge's factor), where `transition_d` is
// interiorSimplification with transitionErrors of the block's Λ.
int interiorFactor(TessellationRule rule, int block_cells, const int (&edge_factors)[4],
                   int interior_d, int transition_d);

// b / 2^d.
inline int tessellationFactor(int block_cells, int d)
{
    return block_cells >> d;
}

} // namespace ridge::lod
