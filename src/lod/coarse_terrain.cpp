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

// The camera's offset e along `axis` (camera depth `ce` along `forward` fixed) at which the
// samples' projections s_k = (p_k·axis − e) / (p_k·forward − ce) are centred, max s + min s =
// 0, by bisection (the sum decreases with e); `fallback` when the centred extent would leave
// [−k, k] (k: the margin's tangent).
double centredOffset(const std::vector<glm::dvec3>& samples, glm::dvec3 axis, glm::dvec3 forward,
                     double ce, double k, double fallback)
{
    auto extent = [&](double e, double& lo, double& hi) {
        lo = INFINITY;
        hi = -INFINITY;
        for (const glm::dvec3& p : samples) {
            const double s = (glm::dot(p, axis) - e) / (glm::dot(p, forward) - ce);
            lo = std::min(lo, s);
            hi = std::max(hi, s);
        }
    };
    double lo = 0, hi = 0;
    extent(fallback, lo, hi);
    // Bracket: moving e by the samples' whole spread along the axis (plus a metre) shifts
    // every projection past the centre.
    double a_lo = INFINITY, a_hi = -INFINITY;
    for (const glm::dvec3& p : samples) {
        a_lo = std::min(a_lo, glm::dot(p, axis));
        a_hi = std::max(a_hi, glm::dot(p, axis));
    }
    double below = fallback - (a_hi - a_lo) - 1.0, above = fallback + (a_hi - a_lo) + 1.0;
    for (int i = 0; i < 60; ++i) {
        const double mid = 0.5 * (below + above);
        extent(mid, lo, hi);
        (lo + hi > 0 ? below : above) = mid;
    }
    const double e = 0.5 * (below + above);
    extent(e, lo, hi);
    const double tolerance = 1e-9 * k;
    return lo >= -k - tolerance && hi <= k + tolerance ? e : fallback;
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
    min_height_ = box_.min.z;
    max_height_ = box_.max.z;
}

CoarseTerrain::CoarseTerrain(TerrainFrame frame, double min_height, double max_height,
                             std::vector<uint16_t> root_codes, HeightQuantization quantization)
    : CoarseTerrain(frame, frame.patchBox(PatchId{0, 0, 0}, min_height, max_height),
                    std::move(root_codes), quantization)
{
    min_height_ = min_height;
    max_height_ = max_height;
}

CoarseTerrain CoarseTerrain::exaggerated(double exaggeration) const
{
    checkParameter("exaggeration", exaggeration, SelectionSettings::kExaggerationRange);
    CoarseTerrain out = *this;
    out.min_height_ = exaggeration * min_height_;
    out.max_height_ = exaggeration * max_height_;
    if (box_.oriented) {
        out.box_ = frame_.patchBox(PatchId{0, 0, 0}, out.min_height_, out.max_height_);
    } else {
        out.box_.min.z = exaggeration * box_.min.z;
        out.box_.max.z = exaggeration * box_.max.z;
    }
    // k · (offset + scale · code): the ground scales with the heights, exactly.
    out.quantization_.offset = exaggeration * quantization_.offset;
    out.quantization_.scale = exaggeration * quantization_.scale;
    return out;
}

double CoarseTerrain::groundHeight(double x, double y) const
{
    const double point[2] = {x, y};
    checkParameters("ground point (x, y)", point, 2, ValueRange::any());
    return groundAt(frame_.columnOf(x), frame_.rowOf(y));
}

double CoarseTerrain::groundUnder(glm::dvec3 world) const
{
    checkParameters("ground point", &world.x, 3, ValueRange::any());
    const glm::dvec3 g = frame_.gridOf(world);
    return groundAt(g.x, g.y);
}

double CoarseTerrain::groundAt(double column, double row) const
{
    const double step = double(frame_.geometry().step(0));
    // Level-0 sample coordinates; ±inf for huge finite x, y over a small spacing, which clamps.
    const double i = clampToSamples(column / step, n_ - 1);
    const double j = clampToSamples(row / step, n_ - 1);
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
    const glm::dvec3 grid = frame_.gridOf(position);
    const double above = frame_.onEllipsoid() ? grid.z - groundAt(grid.x, grid.y)
                                              : position.z - groundHeight(position.x, position.y);
    const double to_box = distanceToBox(position, box_);
    // Reverse-Z float depth keeps precision for a small near plane; it only has to stay in
    // front of the closest surface.
    near_m = std::clamp(0.25 * std::max(above, to_box), 0.05, 1e5);
    double farthest = 0.0;
    for (int k = 0; k < 8; ++k) {
        const glm::dvec3 corner((k & 1) ? box_.max.x : box_.min.x,
                                (k & 2) ? box_.max.y : box_.min.y,
                                (k & 4) ? box_.max.z : box_.min.z);
        const glm::dvec3 world = box_.oriented ? box_.origin + box_.axes * corner : corner;
        farthest = std::max(farthest, glm::length(world - position));
    }
    far_m = std::max(farthest * 1.5, near_m * 2.0);
}

std::vector<glm::dvec3> CoarseTerrain::surfaceSamples() const
{
    // Root samples inside the valid extent, plus its last column and row (which fall between
    // root samples when the extent is not a multiple of the root's step).
    const PyramidGeometry& g = frame_.geometry();
    const int64_t step = g.step(0);
    auto lines = [step](int count) {
        std::vector<double> at;
        for (int64_t k = 0; k < count - 1; k += step)
            at.push_back(double(k));
        at.push_back(double(count - 1));
        return at;
    };
    const std::vector<double> columns = lines(g.width()), rows = lines(g.height());
    std::vector<glm::dvec3> samples;
    samples.reserve(columns.size() * rows.size());
    for (const double row : rows)
        for (const double column : columns) {
            if (frame_.onEllipsoid()) {
                samples.push_back(frame_.worldOf(column, row, groundAt(column, row)));
                continue;
            }
            const double x = frame_.xOf(column), y = frame_.yOf(row);
            samples.emplace_back(x, y, groundHeight(x, y));
        }
    return samples;
}

Camera CoarseTerrain::defaultCamera(Viewport viewport, double fov_y_degrees) const
{
    // The field of view and viewport, validated by Camera before any arithmetic (the fit
    // divides by the half-angles' tangents).
    const Camera probe(glm::dvec3(0.0, 0.0, 1.0), glm::dvec3(0.0), fov_y_degrees, viewport, 1.0,
                       2.0); // throws for a viewport Camera refuses

    // The direction, in the local frame at the terrain's centre (the world axes on a plane):
    // from the south-south-west, 35° above the horizon; straight down, north up, over a
    // globe frame that spans more than 60° (a continent or the whole Earth).
    const PyramidGeometry& g = frame_.geometry();
    const double centre_column = 0.5 * (g.width() - 1), centre_row = 0.5 * (g.height() - 1);
    const EnuBasis local = frame_.basisAt(centre_column, centre_row);
    const bool from_above = frame_.onEllipsoid() &&
                            std::max((g.width() - 1) * frame_.columnAngle(),
                                     (g.height() - 1) * frame_.rowAngle()) > std::numbers::pi / 3;
    const double azimuth = 200.0 * std::numbers::pi / 180.0;
    const double elevation = from_above ? std::numbers::pi / 2 : 35.0 * std::numbers::pi / 180.0;
    const glm::dvec3 forward =
        local.matrix() * glm::dvec3(-std::sin(azimuth) * std::cos(elevation),
                                    -std::cos(azimuth) * std::cos(elevation), -std::sin(elevation));
    // The basis Camera derives from a forward vector and its world up (camera.cpp):
    // right = forward × up; north is that up when looking straight down.
    const glm::dvec3 world_up = from_above ? local.north : local.up;
    const glm::dvec3 right = glm::normalize(glm::cross(forward, world_up));
    const glm::dvec3 up = glm::cross(right, forward);

    // The position: the nearest from which every sample of the surface lies inside the picture
    // with a 4 % margin, and the surface centred in it. With the orientation fixed this is
    // exact: in camera axes (a right, b up, c forward) a point is inside when
    // |a − a_e| ≤ k_x (c − c_e) and |b − b_e| ≤ k_y (c − c_e); the tightest eye meets the
    // extreme points' bounding planes: c_e = (Q − P) / 2k, a_e = (P + Q) / 2 with
    // P = max(a − k c), Q = min(a + k c), per axis, and the smaller c_e (further back) of the
    // two axes serves both. Framing the surface rather than its bounding box keeps a tall
    // summit from leaving the terrain a fifth of the frame.
    const double ky = 0.92 * std::tan(0.5 * probe.fovY());
    const double kx = 0.92 * std::tan(0.5 * probe.fovX());
    double pa = -INFINITY, qa = INFINITY, pb = -INFINITY, qb = INFINITY;
    glm::dvec3 centre(0.0);
    const std::vector<glm::dvec3> samples = surfaceSamples();
    for (const glm::dvec3& p : samples) {
        const double a = glm::dot(p, right), b = glm::dot(p, up), c = glm::dot(p, forward);
        pa = std::max(pa, a - kx * c);
        qa = std::min(qa, a + kx * c);
        pb = std::max(pb, b - ky * c);
        qb = std::min(qb, b + ky * c);
        centre += p;
    }
    centre /= double(samples.size());
    const double ce = std::min((qa - pa) / (2.0 * kx), (qb - pb) / (2.0 * ky));
    // On the looser axis the planes' midpoint is not the pixels' midpoint (near samples move
    // further on screen than far ones): centre the projected extent itself, unless that would
    // push a sample past the margin.
    const double ae = centredOffset(samples, right, forward, ce, kx, 0.5 * (pa + qa));
    const double be = centredOffset(samples, up, forward, ce, ky, 0.5 * (pb + qb));
    const glm::dvec3 position = right * ae + up * be + forward * ce;
    // Looking along `forward`, at the depth of the surface's centre.
    const double depth = std::max(glm::dot(centre - position, forward), 1.0);
    double near_m = 1.0, far_m = 1e6;
    clipPlanesFor(position, near_m, far_m);
    return Camera(position, position + forward * depth, fov_y_degrees, viewport, near_m, far_m,
                  world_up);
}

} // namespace ridge::lod
