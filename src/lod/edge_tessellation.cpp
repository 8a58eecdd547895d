#include "ridge/lod/edge_tessellation.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <limits>

namespace ridge::lod {

EdgeErrors sharedEdgeErrors(const EdgeErrors& a, const EdgeErrors& b, int levels)
{
    EdgeErrors e;
    for (int d = 0; d < levels; ++d)
        e.lambda[d] = std::max(a.lambda[d], b.lambda[d]);
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

} // namespace ridge::lod
