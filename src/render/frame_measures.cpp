#include "ridge/render/frame_measures.h"

#include "ridge/core/error.h"

#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace ridge::render {

namespace {

// Where a ray from `origin` along unit `dir` first meets the sphere of radius `r` about the
// Earth's centre; false when it misses (or the sphere is behind).
bool raySphere(glm::dvec3 origin, glm::dvec3 dir, double r, glm::dvec3& hit)
{
    const double b = glm::dot(origin, dir), c = glm::dot(origin, origin) - r * r;
    const double disc = b * b - c;
    if (disc < 0.0)
        return false;
    const double t = -b - std::sqrt(disc);
    if (t <= 0.0)
        return false;
    hit = origin + t * dir;
    return true;
}

// The pixels of `camera`'s viewport whose ray (a unit direction from the camera) `judged`
// says must meet the terrain, and those of them `background` shows as holes.
template <class Judged>
HoleReport countOverFootprint(const std::vector<uint8_t>& background, const lod::Camera& camera,
                              Judged&& judged)
{
    const lod::Viewport vp = camera.viewport();
    const glm::dmat4 inverse = glm::inverse(camera.viewProjection());
    HoleReport report;
    for (int y = 0; y < vp.height; ++y)
        for (int x = 0; x < vp.width; ++x) {
            const glm::dvec4 ndc((x + 0.5) / vp.width * 2 - 1, 1 - (y + 0.5) / vp.height * 2, 1.0,
                                 1.0);
            const glm::dvec4 far_point = inverse * ndc;
            // viewProjection() is camera-relative: the unprojected point is a direction.
            const glm::dvec3 dir = glm::normalize(glm::dvec3(far_point) / far_point.w);
            if (!judged(dir))
                continue;
            ++report.footprint_pixels;
            if (background[size_t(y) * vp.width + x] && report.hole_pixels++ == 0) {
                report.first_x = x;
                report.first_y = y;
            }
        }
    return report;
}

// The globe's judgement: from outside the sphere that holds all the terrain (a + max), a ray
// that meets the sphere inside all of it (b + min: within the ellipsoid at the lowest height
// everywhere) must cross the surface, where the grid covers both points (a sample in from its
// edges; a wrapping grid has no east and west edge), unless it grazes the limb.
HoleReport countGlobeHolePixels(const std::vector<uint8_t>& background, const lod::Camera& camera,
                                const lod::TerrainFrame& frame, double min_height,
                                double max_height, double limb_pixels)
{
    const glm::dvec3 pos = camera.position();
    const lod::Ellipsoid& e = frame.geodetic().ellipsoid;
    const double outer = e.a + max_height + 1.0, inner = e.b() + min_height - 1.0;
    if (glm::length(pos) <= outer || inner <= 0.0)
        return {};
    const PyramidGeometry& g = frame.geometry();
    const bool wraps = frame.geodetic().wrap_columns > 0;
    const double pixel_angle = 2.0 * std::tan(0.5 * camera.fovY()) / camera.viewport().height;
    auto covered = [&](glm::dvec3 p) {
        const glm::dvec3 q = frame.gridOf(p);
        const bool rows = (frame.poleRow(0.0) || q.y > 1.0) &&
                          (frame.poleRow(double(g.height() - 1)) || q.y < g.height() - 2.0);
        return rows && (wraps || (q.x > 1.0 && q.x < g.width() - 2.0));
    };
    return countOverFootprint(background, camera, [&](glm::dvec3 dir) {
        // Near the limb the drawn globe's edge may fall short of the true one by what ε
        // allows: a ray is judged when it passes at least `limb_pixels` inside the inner
        // sphere's silhouette (its closest approach to the centre that far within).
        const double closest = glm::length(pos - glm::dot(pos, dir) * dir);
        if (closest > inner - limb_pixels * pixel_angle * glm::length(pos))
            return false;
        glm::dvec3 in_hit, out_hit;
        return raySphere(pos, dir, inner, in_hit) && raySphere(pos, dir, outer, out_hit) &&
               covered(in_hit) && covered(out_hit);
    });
}

} // namespace

HoleReport countHolePixels(const std::vector<uint8_t>& background, const lod::Camera& camera,
                           const lod::TerrainFrame& frame, double min_height, double max_height,
                           double limb_px, double surface_under_camera)
{
    const lod::Viewport vp = camera.viewport();
    if (background.size() != size_t(vp.width) * vp.height)
        throw Error("countHolePixels: the background mask is not the camera's viewport");
    if (frame.onEllipsoid())
        return countGlobeHolePixels(background, camera, frame, min_height, max_height, limb_px);
    const glm::dvec3 pos = camera.position();
    const double sx = frame.spacingX(), sy = frame.spacingY();
    auto inside = [&](glm::dvec3 p) {
        return p.x > sx && p.y > sy && p.x < frame.extentX() - sx && p.y < frame.extentY() - sy;
    };
    // Inside the slab a camera may stand under a ridge: its rays are judged from itself only
    // when it is known to be above the drawn surface where it stands (the header).
    const bool above_slab = pos.z >= max_height + 1.0;
    const bool above_surface = !above_slab && !std::isnan(surface_under_camera) &&
                               pos.z >= surface_under_camera + 1.0 && inside(pos);
    if (!above_slab && !above_surface)
        return HoleReport{};
    return countOverFootprint(background, camera, [&](glm::dvec3 dir) {
        if (!(dir.z < 0))
            return false;
        auto at = [&](double z) { return pos + dir * ((z - pos.z) / dir.z); };
        return (above_surface || inside(at(max_height + 1.0))) && inside(at(min_height - 1.0));
    });
}

namespace {

// Twice the signed area of the triangle (a, b, c) of the xy plane.
double doubledArea(glm::dvec2 a, glm::dvec2 b, glm::dvec2 c)
{
    return (b.y - c.y) * (a.x - c.x) + (c.x - b.x) * (a.y - c.y);
}

// p's barycentric weights l[0..2] on a, b, c (det = doubledArea(a, b, c)); true when all are at
// least -tolerance (p in the triangle).
bool barycentric(glm::dvec2 a, glm::dvec2 b, glm::dvec2 c, double det, glm::dvec2 p,
                 double tolerance, double (&l)[3])
{
    l[0] = ((b.y - c.y) * (p.x - c.x) + (c.x - b.x) * (p.y - c.y)) / det;
    l[1] = ((c.y - a.y) * (p.x - c.x) + (a.x - c.x) * (p.y - c.y)) / det;
    l[2] = 1.0 - l[0] - l[1];
    return l[0] >= -tolerance && l[1] >= -tolerance && l[2] >= -tolerance;
}

} // namespace

double surfaceHeightUnder(const CapturedSurface& surface, const lod::TerrainFrame& frame, double x,
                          double y)
{
    if (frame.onEllipsoid())
        throw Error("surfaceHeightUnder: plane terrain frames only");
    // Camera-relative, as captured: the point too, so that the test is as precise as the
    // vertices.
    const glm::dvec2 p(x - surface.camera_position.x, y - surface.camera_position.y);
    double highest = std::numeric_limits<double>::quiet_NaN();
    const std::vector<CapturedVertex>& v = surface.vertices;
    for (size_t t = 0; t + 2 < v.size(); t += 3) {
        if (v[t].skirt || v[t + 1].skirt || v[t + 2].skirt)
            continue;
        const glm::dvec2 a(v[t].x, v[t].y), b(v[t + 1].x, v[t + 1].y), c(v[t + 2].x, v[t + 2].y);
        const double det = doubledArea(a, b, c);
        if (std::abs(det) < 1e-9)
            continue; // a wall of the clipping stage, or degenerate
        double l[3];
        if (!barycentric(a, b, c, det, p, 1e-9, l))
            continue;
        const double z = l[0] * v[t].z + l[1] * v[t + 1].z + l[2] * v[t + 2].z;
        highest = std::isnan(highest) ? z : std::max(highest, z);
    }
    return highest + surface.camera_position.z;
}

float SampleHeights::at(int column, int row) const
{
    if (column < x0 || row < y0 || column >= x0 + width || row >= y0 + height)
        return std::numeric_limits<float>::quiet_NaN();
    return z[size_t(row - y0) * size_t(width) + size_t(column - x0)];
}

namespace {

// A triangle's vertices in finest (column, row) and terrain-frame z; vertices lie on
// samples, and rounding undoes the float error of camera-relative x, y.
bool sampleTriangle(const CapturedVertex* v, glm::dvec3 c, const lod::TerrainFrame& frame,
                    glm::dvec3 q[3])
{
    if (v[0].skirt || v[1].skirt || v[2].skirt)
        return false;
    if (!frame.onEllipsoid()) {
        for (int k = 0; k < 3; ++k)
            q[k] = {std::round(frame.columnOf(v[k].x + c.x)), std::round(frame.rowOf(v[k].y + c.y)),
                    double(v[k].z) + c.z};
        return true;
    }
    // The globe: grid positions through the frame's inverse (z is filled per sample by the
    // caller from the drawn point). A pole vertex has no column: its triangles are left out.
    for (int k = 0; k < 3; ++k) {
        const glm::dvec3 g = frame.gridOf(c + glm::dvec3(v[k].x, v[k].y, v[k].z));
        q[k] = {std::round(g.x), std::round(g.y), g.z};
        if (frame.poleRow(q[k].y))
            return false;
    }
    // Across a wrapping grid's edge meridian: all corners in one period.
    if (const double period = double(frame.geodetic().wrap_columns);
        period > 0 &&
        std::max({q[0].x, q[1].x, q[2].x}) - std::min({q[0].x, q[1].x, q[2].x}) > 0.5 * period)
        for (int k = 0; k < 3; ++k)
            if (q[k].x < 0.5 * period)
                q[k].x += period;
    return true;
}

} // namespace

SampleHeights surfaceHeightsAtSamples(const CapturedSurface& s, const lod::TerrainFrame& frame)
{
    const int W = frame.geometry().width(), H = frame.geometry().height();
    const glm::dvec3 c = s.camera_position;
    // The window first: the samples the surface's triangles span, within the grid.
    double lo_x = W, lo_y = H, hi_x = -1, hi_y = -1;
    glm::dvec3 q[3];
    for (size_t t = 0; t + 2 < s.vertices.size(); t += 3)
        if (sampleTriangle(&s.vertices[t], c, frame, q))
            for (const glm::dvec3& p : q) {
                lo_x = std::min(lo_x, p.x);
                lo_y = std::min(lo_y, p.y);
                hi_x = std::max(hi_x, p.x);
                hi_y = std::max(hi_y, p.y);
            }
    SampleHeights out;
    out.x0 = std::clamp(int(lo_x), 0, W);
    out.y0 = std::clamp(int(lo_y), 0, H);
    out.width = std::max(0, std::min(W - 1, int(hi_x)) - out.x0 + 1);
    out.height = std::max(0, std::min(H - 1, int(hi_y)) - out.y0 + 1);
    out.z.assign(size_t(out.width) * size_t(out.height), std::numeric_limits<float>::quiet_NaN());
    for (size_t t = 0; t + 2 < s.vertices.size(); t += 3) {
        if (!sampleTriangle(&s.vertices[t], c, frame, q))
            continue;
        const double det = doubledArea(glm::dvec2(q[0]), glm::dvec2(q[1]), glm::dvec2(q[2]));
        if (std::abs(det) < 1e-12)
            continue; // a wall of the clipping shader, or degenerate
        const int c0 = std::max(out.x0, int(std::ceil(std::min({q[0].x, q[1].x, q[2].x}) - 1e-6)));
        const int c1 = std::min(out.x0 + out.width - 1,
                                int(std::floor(std::max({q[0].x, q[1].x, q[2].x}) + 1e-6)));
        const int r0 = std::max(out.y0, int(std::ceil(std::min({q[0].y, q[1].y, q[2].y}) - 1e-6)));
        const int r1 = std::min(out.y0 + out.height - 1,
                                int(std::floor(std::max({q[0].y, q[1].y, q[2].y}) + 1e-6)));
        for (int r = r0; r <= r1; ++r)
            for (int col = c0; col <= c1; ++col) {
                double l[3];
                if (!barycentric(glm::dvec2(q[0]), glm::dvec2(q[1]), glm::dvec2(q[2]), det,
                                 glm::dvec2(col, r), 1e-6, l))
                    continue;
                float z = float(l[0] * q[0].z + l[1] * q[1].z + l[2] * q[2].z);
                if (frame.onEllipsoid()) {
                    // The flat triangle's point over the sample, its height along the normal
                    // (the chord's sag included, as drawn).
                    const CapturedVertex* v = &s.vertices[t];
                    glm::dvec3 drawn(0.0);
                    for (int k = 0; k < 3; ++k)
                        drawn += l[k] * glm::dvec3(v[k].x, v[k].y, v[k].z);
                    z = float(frame.gridOf(c + drawn).z);
                }
                if (col >= W)
                    continue; // past a wrapping grid's last column: its copy at the start
                float& h = out.z[size_t(r - out.y0) * size_t(out.width) + size_t(col - out.x0)];
                // Seams between levels cover a sample twice: the upper surface is what shows.
                h = std::isnan(h) ? z : std::max(h, z);
            }
    }
    return out;
}

PoppingReport measurePopping(const SampleHeights& before, const SampleHeights& after,
                             const lod::TerrainFrame& frame, const lod::Camera& camera)
{
    PoppingReport report;
    const lod::Viewport vp = camera.viewport();
    const int x0 = std::max(before.x0, after.x0), y0 = std::max(before.y0, after.y0);
    const int x1 = std::min(before.x0 + before.width, after.x0 + after.width);
    const int y1 = std::min(before.y0 + before.height, after.y0 + after.height);
    for (int r = y0; r < y1; ++r)
        for (int col = x0; col < x1; ++col) {
            const float a = before.at(col, r), b = after.at(col, r);
            if (std::isnan(a) || std::isnan(b))
                continue;
            const glm::dvec3 pa = frame.onEllipsoid() ? frame.worldOf(col, r, a)
                                                      : glm::dvec3(frame.xOf(col), frame.yOf(r), a);
            const glm::dvec3 pb =
                frame.onEllipsoid() ? frame.worldOf(col, r, b) : glm::dvec3(pa.x, pa.y, b);
            glm::dvec2 xa, xb;
            if (!camera.project(pa, xa) || !camera.project(pb, xb))
                continue;
            const bool in_view =
                (xa.x >= 0 && xa.y >= 0 && xa.x <= vp.width && xa.y <= vp.height) ||
                (xb.x >= 0 && xb.y >= 0 && xb.x <= vp.width && xb.y <= vp.height);
            const double depth = glm::dot(pa - camera.position(), camera.forward());
            if (!in_view || depth < camera.nearPlane())
                continue;
            ++report.samples;
            report.max_px = std::max(report.max_px, glm::length(xa - xb));
            report.max_metres = std::max(report.max_metres, std::abs(double(a) - double(b)));
        }
    return report;
}

} // namespace ridge::render
