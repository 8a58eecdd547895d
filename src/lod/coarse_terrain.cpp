#include "ridge/lod/coarse_terrain.h"

#include "ridge/core/error.h"
#include "ridge/core/parameter_check.h"
#include "ridge/lod/patch_quadtree.h"
#include "ridge/lod/screen_space_error.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace ridge::lod {

namespace {

// A fractional sample index clamped to [0, last]. NaN goes to 0: for finite coordinates and a
// valid frame none arises, but converting one to an index would be undefined behaviour and a
// read anywhere, so the comparison is written to send NaN to the safe side.
double clampToSamples(double index, int last)
{
    return index > 0.0 ? std::min(index, double(last)) : 0.0;
}

} // namespace

CoarseTerrain::CoarseTerrain(TerrainFrame frame, Box root_box, std::vector<uint16_t> root_codes,
                             HeightQuantization quantization)
    : frame_(std::move(frame)), box_(root_box), codes_(std::move(root_codes)),
      quantization_(quantization), n_(frame_.geometry().patchSize())
{
    if (n_ < 2 || codes_.size() != size_t(n_) * size_t(n_))
        throw Error("coarse terrain: the level-0 patch has " + std::to_string(codes_.size()) +
                    " codes, expected " + std::to_string(n_) + "x" + std::to_string(n_));
    checkParameter("terrain spacing x (m)", frame_.spacingX(), ValueRange::positive());
    checkParameter("terrain spacing y (m)", frame_.spacingY(), ValueRange::positive());
}

CoarseTerrain CoarseTerrain::exaggerated(double exaggeration) const
{
    checkParameter("exaggeration", exaggeration, SelectionSettings::kExaggerationRange);
    CoarseTerrain out = *this;
    out.box_.min.z = exaggeration * box_.min.z;
    out.box_.max.z = exaggeration * box_.max.z;
    // k · (offset + scale · code): the ground scales with the heights, exactly.
    out.quantization_.offset = exaggeration * quantization_.offset;
    out.quantization_.scale = exaggeration * quantization_.scale;
    return out;
}

double CoarseTerrain::groundHeight(double x, double y) const
{
    const double point[2] = {x, y};
    checkParameters("ground point (x, y)", point, 2, ValueRange::any());
    const double step = double(frame_.geometry().step(0));
    // Level-0 sample coordinates; ±inf for huge finite x, y over a small spacing, which clamps.
    const double i = clampToSamples(frame_.columnOf(x) / step, n_ - 1);
    const double j = clampToSamples(frame_.rowOf(y) / step, n_ - 1);
    const int i0 = std::min(int(i), n_ - 2), j0 = std::min(int(j), n_ - 2);
    const double fx = i - i0, fy = j - j0;
    auto code = [&](int a, int b) { return double(codes_[size_t(b) * size_t(n_) + size_t(a)]); };
    const double c = (code(i0, j0) * (1 - fx) + code(i0 + 1, j0) * fx) * (1 - fy) +
                     (code(i0, j0 + 1) * (1 - fx) + code(i0 + 1, j0 + 1) * fx) * fy;
    return quantization_.toMetres(c);
}

void CoarseTerrain::clipPlanesFor(glm::dvec3 position, double& near_m, double& far_m) const
{
    checkParameters("camera position", &position.x, 3, kCameraCoordinateRange);
    const double above = position.z - groundHeight(position.x, position.y);
    const double to_box = distanceToBox(position, box_);
    // Reverse-Z float depth keeps precision for a small near plane; it only has to stay in
    // front of the closest surface.
    near_m = std::clamp(0.25 * std::max(above, to_box), 0.05, 1e5);
    double farthest = 0.0;
    for (int k = 0; k < 8; ++k) {
        const glm::dvec3 corner((k & 1) ? box_.max.x : box_.min.x,
                                (k & 2) ? box_.max.y : box_.min.y,
                                (k & 4) ? box_.max.z : box_.min.z);
        farthest = std::max(farthest, glm::length(corner - position));
    }
    far_m = std::max(farthest * 1.5, near_m * 2.0);
}

Camera CoarseTerrain::defaultCamera(Viewport viewport, double fov_y_degrees) const
{
    // The box's heights are the index's floats; summed in float as the renderer always did,
    // so that the default view (and the reference renders made with it) stays bit-identical.
    const float lo = float(box_.min.z), hi = float(box_.max.z);
    const glm::dvec3 centre(0.5 * frame_.extentX(), 0.5 * frame_.extentY(), 0.5 * (lo + hi));
    const double dz = double(hi - lo);
    const double radius = 0.5 * std::sqrt(frame_.extentX() * frame_.extentX() +
                                          frame_.extentY() * frame_.extentY() + dz * dz);
    const double azimuth = 200.0 * std::numbers::pi / 180.0;
    const double elevation = 35.0 * std::numbers::pi / 180.0;
    const glm::dvec3 dir(std::sin(azimuth) * std::cos(elevation),
                         std::cos(azimuth) * std::cos(elevation), std::sin(elevation));
    auto framed = [&](const Camera& camera) {
        for (int k = 0; k < 8; ++k) {
            const glm::dvec3 corner((k & 1) ? box_.max.x : box_.min.x,
                                    (k & 2) ? box_.max.y : box_.min.y,
                                    (k & 4) ? box_.max.z : box_.min.z);
            glm::dvec2 px;
            if (!camera.project(corner, px) || px.x < 0.04 * viewport.width ||
                px.x > 0.96 * viewport.width || px.y < 0.04 * viewport.height ||
                px.y > 0.96 * viewport.height)
                return false;
        }
        return true;
    };
    double distance = 0.25 * radius;
    for (;;) {
        const glm::dvec3 position = centre + dir * distance;
        double near_m = 1.0, far_m = 1e6;
        clipPlanesFor(position, near_m, far_m);
        const Camera camera(position, centre, fov_y_degrees, viewport, near_m, far_m);
        if (framed(camera) || distance > 100.0 * radius)
            return camera;
        distance *= 1.05;
    }
}

} // namespace ridge::lod
