#include "ridge/render/frame_measures.h"

#include "ridge/core/error.h"

#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace ridge::render {

HoleReport countHolePixels(const std::vector<uint8_t>& background, const lod::Camera& camera,
                           const lod::TerrainFrame& frame, double min_height, double max_height)
{
    const lod::Viewport vp = camera.viewport();
    if (background.size() != size_t(vp.width) * vp.height)
        throw Error("countHolePixels: the background mask is not the camera's viewport");
    HoleReport report;
    const glm::dvec3 pos = camera.position();
    const glm::dmat4 inverse = glm::inverse(camera.viewProjection());
    const double sx = frame.spacingX(), sy = frame.spacingY();
    auto inside = [&](glm::dvec3 p) {
        return p.x > sx && p.y > sy && p.x < frame.extentX() - sx && p.y < frame.extentY() - sy;
    };
    for (int y = 0; y < vp.height; ++y)
        for (int x = 0; x < vp.width; ++x) {
            const glm::dvec4 ndc((x + 0.5) / vp.width * 2 - 1, 1 - (y + 0.5) / vp.height * 2, 1.0,
                                 1.0);
            const glm::dvec4 far_point = inverse * ndc;
            // viewProjection() is camera-relative: the unprojected point is a direction.
            const glm::dvec3 dir = glm::normalize(glm::dvec3(far_point) / far_point.w);
            if (!(dir.z < 0))
                continue;
            auto at = [&](double z) { return pos + dir * ((z - pos.z) / dir.z); };
            // A camera inside the slab may stand under a ridge: its rays are not judged.
            if (pos.z < max_height + 1.0 || !inside(at(max_height + 1.0)) ||
                !inside(at(min_height - 1.0)))
                continue;
            ++report.footprint_pixels;
            if (background[size_t(y) * vp.width + x] && report.hole_pixels++ == 0) {
                report.first_x = x;
                report.first_y = y;
            }
        }
    return report;
}

std::vector<float> surfaceHeightsAtSamples(const CapturedSurface& s, const lod::TerrainFrame& frame)
{
    const int W = frame.geometry().width(), H = frame.geometry().height();
    std::vector<float> heights(size_t(W) * H, std::numeric_limits<float>::quiet_NaN());
    const glm::dvec3 c = s.camera_position;
    for (size_t t = 0; t + 2 < s.vertices.size(); t += 3) {
        const CapturedVertex* v = &s.vertices[t];
        if (v[0].skirt || v[1].skirt || v[2].skirt)
            continue;
        glm::dvec3 q[3];
        // Vertices lie on samples; rounding undoes the float error of camera-relative x, y.
        for (int k = 0; k < 3; ++k)
            q[k] = {std::round(frame.columnOf(v[k].x + c.x)), std::round(frame.rowOf(v[k].y + c.y)),
                    double(v[k].z) + c.z};
        const double det =
            (q[1].y - q[2].y) * (q[0].x - q[2].x) + (q[2].x - q[1].x) * (q[0].y - q[2].y);
        if (std::abs(det) < 1e-12)
            continue; // a wall of the clipping shader, or degenerate
        const int c0 = std::max(0, int(std::ceil(std::min({q[0].x, q[1].x, q[2].x}) - 1e-6)));
        const int c1 = std::min(W - 1, int(std::floor(std::max({q[0].x, q[1].x, q[2].x}) + 1e-6)));
        const int r0 = std::max(0, int(std::ceil(std::min({q[0].y, q[1].y, q[2].y}) - 1e-6)));
        const int r1 = std::min(H - 1, int(std::floor(std::max({q[0].y, q[1].y, q[2].y}) + 1e-6)));
        for (int r = r0; r <= r1; ++r)
            for (int col = c0; col <= c1; ++col) {
                const double l0 =
                    ((q[1].y - q[2].y) * (col - q[2].x) + (q[2].x - q[1].x) * (r - q[2].y)) / det;
                const double l1 =
                    ((q[2].y - q[0].y) * (col - q[2].x) + (q[0].x - q[2].x) * (r - q[2].y)) / det;
                const double l2 = 1.0 - l0 - l1;
                if (l0 < -1e-6 || l1 < -1e-6 || l2 < -1e-6)
                    continue;
                const float z = float(l0 * q[0].z + l1 * q[1].z + l2 * q[2].z);
                float& h = heights[size_t(r) * W + col];
                // Seams between levels cover a sample twice: the upper surface is what shows.
                h = std::isnan(h) ? z : std::max(h, z);
            }
    }
    return heights;
}

PoppingReport measurePopping(const std::vector<float>& before, const std::vector<float>& after,
                             const lod::TerrainFrame& frame, const lod::Camera& camera)
{
    const int W = frame.geometry().width(), H = frame.geometry().height();
    if (before.size() != size_t(W) * H || after.size() != before.size())
        throw Error("measurePopping: the height grids are not the terrain's finest grid");
    PoppingReport report;
    const lod::Viewport vp = camera.viewport();
    for (int r = 0; r < H; ++r)
        for (int col = 0; col < W; ++col) {
            const float a = before[size_t(r) * W + col], b = after[size_t(r) * W + col];
            if (std::isnan(a) || std::isnan(b))
                continue;
            const glm::dvec3 pa(frame.xOf(col), frame.yOf(r), a), pb(pa.x, pa.y, b);
            glm::dvec2 xa, xb;
            if (!camera.project(pa, xa) || !camera.project(pb, xb))
                continue;
            const bool in_view = (xa.x >= 0 && xa.y >= 0 && xa.x <= vp.width && xa.y <= vp.height) ||
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
