#include "ridge/lod/edge_tessellation.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <iterator>
#include <limits>

namespace ridge::lod {

EdgeErrors sharedEdgeErrors(const EdgeErrors& a, const EdgeErrors& b, int levels)
{
    EdgeErrors e;
    for (int d = 0; d < levels; ++d)
        e.lambda[d] = std::max(a.lambda[d], b.lambda[d]);
    e.patch_error = std::max(a.patch_error, b.patch_error);
    return e;
}

double projectedVerticalSegment(const glm::dmat4& view_projection, Viewport viewport,
                                glm::dvec3 centre_rel, double length)
{
    const glm::dvec3 half(0.0, 0.0, 0.5 * length);
    const glm::dvec4 lo = view_projection * glm::dvec4(centre_rel - half, 1.0);
    const glm::dvec4 hi = view_projection * glm::dvec4(centre_rel + half, 1.0);
    // Same guard as the shader: an end behind the camera cannot be measured on screen.
    if (lo.w <= 1e-6 || hi.w <= 1e-6)
        return std::numeric_limits<double>::infinity();
    const glm::dvec2 scale(0.5 * viewport.width, 0.5 * viewport.height);
    return glm::length((glm::dvec2(hi) / hi.w - glm::dvec2(lo) / lo.w) * scale);
}

int edgeSimplification(const glm::dmat4& view_projection, Viewport viewport, glm::dvec3 centre_rel,
                       const EdgeErrors& errors, int levels, double epsilon_px)
{
    for (int d = levels; d >= 1; --d)
        if (projectedVerticalSegment(view_projection, viewport, centre_rel, errors.lambda[d - 1]) <
            epsilon_px)
            return d;
    return 0;
}

glm::dvec3 nearestPointOfSegment(glm::dvec3 a, glm::dvec3 b)
{
    const glm::dvec3 ab = b - a;
    const double t = std::clamp(-glm::dot(a, ab) / std::max(glm::dot(ab, ab), 1e-30), 0.0, 1.0);
    return a + t * ab;
}

EdgeErrors transitionErrors(const EdgeErrors& errors)
{
    // 2λ^(d) + Err(P) = 2Λ^(d) − Err(P), in float as the shader computes it.
    EdgeErrors doubled;
    for (int d = 0; d < kMaxBlockLevels; ++d)
        doubled.lambda[d] = 2.0f * errors.lambda[d] - errors.patch_error;
    doubled.patch_error = errors.patch_error;
    return doubled;
}

int edgeSimplification(const glm::dmat4& view_projection, Viewport viewport, glm::dvec3 a,
                       glm::dvec3 centre, glm::dvec3 b, const EdgeErrors& errors, int levels,
                       double epsilon_px, TessellationRule rule)
{
    if (rule == TessellationRule::Paper)
        return edgeSimplification(view_projection, viewport, centre, errors, levels, epsilon_px);
    // 2λ_e^(d) + Err(P): it bounds the transition triangles towards a finer interior too (the
    // header).
    const EdgeErrors doubled = transitionErrors(errors);
    auto at = [&](glm::dvec3 p) {
        return edgeSimplification(view_projection, viewport, p, doubled, levels, epsilon_px);
    };
    // Where Λ_e projects largest: the near end, or the edge's nearest point when the camera
    // is abreast of the edge (see the header).
    return std::min({at(a), at(centre), at(b), at(nearestPointOfSegment(a, b))});
}

int interiorSimplification(const glm::dmat4& view_projection, Viewport viewport,
                           const glm::dvec3 (&corners)[4], glm::dvec3 centre, glm::dvec3 box_lo,
                           glm::dvec3 box_hi, const EdgeErrors& own, int levels, double epsilon_px)
{
    auto at = [&](glm::dvec3 p) {
        return edgeSimplification(view_projection, viewport, p, own, levels, epsilon_px);
    };
    int d = std::min(at(glm::clamp(glm::dvec3(0.0), box_lo, box_hi)), at(centre));
    for (const glm::dvec3& c : corners)
        d = std::min(d, at(c));
    return d;
}

int interiorFactor(TessellationRule rule, int block_cells, const int (&edge_factors)[4],
                   int interior_d, int transition_d)
{
    const auto [lo, hi] = std::minmax_element(std::begin(edge_factors), std::end(edge_factors));
    if (rule == TessellationRule::Paper)
        return *lo;
    const int own = tessellationFactor(block_cells, interior_d);
    if (*hi <= own)
        return own; // every transition steps from this interior to a coarser edge
    // A finer edge would make transition triangles at the interior's own level: they need
    // its 2λ + Err(P) test, and need not be finer than the finest edge.
    return std::min(tessellationFactor(block_cells, transition_d), *hi);
}

} // namespace ridge::lod
