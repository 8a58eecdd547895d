#include "ridge/lod/frustum.h"

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

namespace ridge::lod {

Frustum::Frustum(const Camera& camera)
{
    // Planes of the camera-relative matrix, then moved to the terrain frame by translating.
    const glm::dmat4 m =
        camera.viewProjection() * glm::translate(glm::dmat4(1.0), -camera.position());
    const glm::dvec4 row0(m[0][0], m[1][0], m[2][0], m[3][0]);
    const glm::dvec4 row1(m[0][1], m[1][1], m[2][1], m[3][1]);
    const glm::dvec4 row2(m[0][2], m[1][2], m[2][2], m[3][2]);
    const glm::dvec4 row3(m[0][3], m[1][3], m[2][3], m[3][3]);
    const glm::dvec4 raw[6] = {row3 + row0, row3 - row0, row3 + row1,
                               row3 - row1, row3 + row2, row3 - row2};
    for (int i = 0; i < 6; ++i)
        planes_[i] = raw[i] / glm::length(glm::dvec3(raw[i]));
}

Visibility Frustum::classify(const Box& box) const
{
    Visibility result = Visibility::Inside;
    for (const glm::dvec4& world_plane : planes_) {
        // An oriented box: the plane in the box's own frame, where it is axis-aligned.
        const glm::dvec4 pl =
            box.oriented ? glm::dvec4(box.directionToLocal(glm::dvec3(world_plane)),
                                      world_plane.w + glm::dot(glm::dvec3(world_plane), box.origin))
                         : world_plane;
        const glm::dvec3 n(pl);
        const glm::dvec3 p_vertex(n.x >= 0 ? box.max.x : box.min.x,
                                  n.y >= 0 ? box.max.y : box.min.y,
                                  n.z >= 0 ? box.max.z : box.min.z);
        if (glm::dot(n, p_vertex) + pl.w < 0.0)
            return Visibility::Outside;
        const glm::dvec3 n_vertex(n.x >= 0 ? box.min.x : box.max.x,
                                  n.y >= 0 ? box.min.y : box.max.y,
                                  n.z >= 0 ? box.min.z : box.max.z);
        if (glm::dot(n, n_vertex) + pl.w < 0.0)
            result = Visibility::Intersecting;
    }
    return result;
}

} // namespace ridge::lod
