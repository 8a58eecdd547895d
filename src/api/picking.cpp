#include "picking.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace ridge::api {
namespace {

// Where the ray enters the box (slab test), +inf when it misses it or the box is behind.
double enterBox(glm::dvec3 o, glm::dvec3 d, glm::dvec3 lo, glm::dvec3 hi)
{
    double t0 = 0.0, t1 = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 3; ++a) {
        if (d[a] == 0.0) {
            if (o[a] < lo[a] || o[a] > hi[a])
                return std::numeric_limits<double>::infinity();
            continue;
        }
        double ta = (lo[a] - o[a]) / d[a], tb = (hi[a] - o[a]) / d[a];
        if (ta > tb)
            std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
        if (t0 > t1)
            return std::numeric_limits<double>::infinity();
    }
    return t0;
}

// Möller & Trumbore (1997), "Fast, Minimum Storage Ray/Triangle Intersection": t of the hit,
// or +inf. Barycentric coordinates may fall short of 0 by 1e-9 of the edge so that a ray
// through a shared edge or vertex is not lost between two triangles.
double hitTriangle(glm::dvec3 o, glm::dvec3 d, glm::dvec3 a, glm::dvec3 b, glm::dvec3 c)
{
    constexpr double kInf = std::numeric_limits<double>::infinity();
    constexpr double kSlack = 1e-9;
    const glm::dvec3 e1 = b - a, e2 = c - a;
    const glm::dvec3 p = glm::cross(d, e2);
    const double det = glm::dot(e1, p);
    if (det == 0.0 || !std::isfinite(det))
        return kInf; // parallel to the triangle, or a degenerate one
    const double inv = 1.0 / det;
    const glm::dvec3 s = o - a;
    const double u = glm::dot(s, p) * inv;
    if (u < -kSlack || u > 1.0 + kSlack)
        return kInf;
    const glm::dvec3 q = glm::cross(s, e1);
    const double v = glm::dot(d, q) * inv;
    if (v < -kSlack || u + v > 1.0 + kSlack)
        return kInf;
    const double t = glm::dot(e2, q) * inv;
    return t > 0.0 ? t : kInf;
}

} // namespace

PickSurface::PickSurface(render::CapturedSurface surface)
    : camera_position_(surface.camera_position)
{
    // Surface triangles by instance (a counting sort: the feedback buffer keeps each draw's
    // order, but the two instance groups are drawn separately).
    const size_t instances = surface.patches.size();
    std::vector<size_t> count(instances + 1, 0);
    const auto& v = surface.vertices;
    auto surfaceTriangle = [&](size_t t) {
        return v[3 * t].skirt == 0 && v[3 * t + 1].skirt == 0 && v[3 * t + 2].skirt == 0 &&
               v[3 * t].instance >= 0 && size_t(v[3 * t].instance) < instances;
    };
    const size_t triangles = v.size() / 3;
    for (size_t t = 0; t < triangles; ++t)
        if (surfaceTriangle(t))
            ++count[size_t(v[3 * t].instance) + 1];
    for (size_t i = 0; i < instances; ++i)
        count[i + 1] += count[i];
    groups_.resize(instances);
    for (size_t i = 0; i < instances; ++i) {
        groups_[i].patch = surface.patches[i];
        groups_[i].first = count[i];
        groups_[i].count = count[i + 1] - count[i];
        groups_[i].min = glm::dvec3(std::numeric_limits<double>::infinity());
        groups_[i].max = -groups_[i].min;
    }
    corners_.resize(3 * count[instances]);
    std::vector<size_t> next(count.begin(), count.end() - 1);
    for (size_t t = 0; t < triangles; ++t) {
        if (!surfaceTriangle(t))
            continue;
        Group& g = groups_[size_t(v[3 * t].instance)];
        const size_t slot = next[size_t(v[3 * t].instance)]++;
        for (int k = 0; k < 3; ++k) {
            const render::CapturedVertex& cv = v[3 * t + size_t(k)];
            const glm::dvec3 p(cv.x, cv.y, cv.z);
            corners_[3 * slot + size_t(k)] = p;
            g.min = glm::min(g.min, p);
            g.max = glm::max(g.max, p);
        }
    }
}

std::optional<SurfaceHit> PickSurface::intersect(glm::dvec3 o, glm::dvec3 d) const
{
    double best = std::numeric_limits<double>::infinity();
    const Group* best_group = nullptr;
    size_t best_triangle = 0;
    for (const Group& g : groups_) {
        if (g.count == 0 || !(enterBox(o, d, g.min, g.max) < best))
            continue;
        for (size_t t = g.first; t < g.first + g.count; ++t) {
            const double hit =
                hitTriangle(o, d, corners_[3 * t], corners_[3 * t + 1], corners_[3 * t + 2]);
            if (hit < best) {
                best = hit;
                best_group = &g;
                best_triangle = t;
            }
        }
    }
    if (!best_group)
        return std::nullopt;
    return SurfaceHit{best,
                      o + best * d,
                      best_group->patch,
                      {corners_[3 * best_triangle], corners_[3 * best_triangle + 1],
                       corners_[3 * best_triangle + 2]}};
}

} // namespace ridge::api
