#include "host_view.h"

#include "ridge/core/error.h"
#include "ridge/core/parameter_check.h"

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace ridge::api {
namespace {

// Eye-space direction (x, y, −1) of NDC point (x_ndc, y_ndc): the x, y rows of a
// perspective projection at eye depth 1 (w = 1) solved for x, y.
glm::dvec3 eyeDirection(const glm::dmat4& p, double x_ndc, double y_ndc)
{
    const double a = p[0][0], b = p[1][0], c = p[0][1], d = p[1][1];
    const double rx = x_ndc + p[2][0] - p[3][0], ry = y_ndc + p[2][1] - p[3][1];
    const double det = a * d - b * c;
    return {(d * rx - b * ry) / det, (a * ry - c * rx) / det, -1.0};
}

// Matrices built in float and widened to double are within 1e-6 of a rotation; the exact
// entries (0, 1, −1) are exact in float too.
constexpr double kRotationTolerance = 1e-5;
constexpr double kExactTolerance = 1e-9;

void requireNear(double value, double expected, const char* what,
                 double tolerance = kExactTolerance)
{
    if (!(std::abs(value - expected) <= tolerance))
        throw Error(std::string("HostView: ") + what);
}

} // namespace

glm::dmat4 matrixOf(const std::array<double, 16>& m)
{
    glm::dmat4 out;
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            out[c][r] = m[size_t(c * 4 + r)];
    return out;
}

std::array<double, 16> arrayOf(const glm::dmat4& m)
{
    std::array<double, 16> out{};
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            out[size_t(c * 4 + r)] = m[c][r];
    return out;
}

glm::dvec3 PixelRays::direction(double x, double y) const
{
    const double x_ndc = 2.0 * x / width - 1.0, y_ndc = 1.0 - 2.0 * y / height;
    return world_from_eye * eyeDirection(projection, x_ndc, y_ndc);
}

HostCamera hostCamera(const HostView& host, const render::TerrainRenderer& renderer,
                      double exaggeration)
{
    // The numbers: finite, a viewport GL can have.
    checkParameters("HostView::view", host.view.data(), 16, ValueRange::any());
    checkParameters("HostView::projection", host.projection.data(), 16, ValueRange::any());
    checkParameter("HostView::width", int64_t{host.width}, 1, lod::kMaxViewportPixels);
    checkParameter("HostView::height", int64_t{host.height}, 1, lod::kMaxViewportPixels);
    const glm::dmat4 v = matrixOf(host.view), p = matrixOf(host.projection);

    // The view: a rigid motion; the eye at −Rᵀt.
    const glm::dmat3 rotation(v);
    const glm::dmat3 gram = glm::transpose(rotation) * rotation;
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r)
            requireNear(gram[c][r], c == r ? 1.0 : 0.0,
                        "view is not a rigid motion (its 3x3 part must be a rotation: no scale "
                        "or shear)",
                        kRotationTolerance);
    requireNear(glm::determinant(rotation), 1.0, "view mirrors (its rotation has determinant -1)",
                kRotationTolerance);
    requireNear(v[0][3], 0.0, "view's last row must be 0 0 0 1");
    requireNear(v[1][3], 0.0, "view's last row must be 0 0 0 1");
    requireNear(v[2][3], 0.0, "view's last row must be 0 0 0 1");
    requireNear(v[3][3], 1.0, "view's last row must be 0 0 0 1");
    const glm::dmat3 world_from_eye = glm::transpose(rotation);
    const glm::dvec3 eye = -(world_from_eye * glm::dvec3(v[3]));
    checkParameters("HostView eye position (local metres)", &eye.x, 3, lod::kCameraCoordinateRange);

    // The projection: perspective, invertible across the screen, depth one way or the other.
    requireNear(p[0][3], 0.0, "projection is not perspective (its last row must be 0 0 -1 0)");
    requireNear(p[1][3], 0.0, "projection is not perspective (its last row must be 0 0 -1 0)");
    requireNear(p[2][3], -1.0, "projection is not perspective (its last row must be 0 0 -1 0)");
    requireNear(p[3][3], 0.0, "projection is not perspective (its last row must be 0 0 -1 0)");
    const double det = p[0][0] * p[1][1] - p[1][0] * p[0][1];
    if (!(std::abs(det) > 0.0) || !std::isfinite(1.0 / det))
        throw Error("HostView: projection maps the whole view onto a line (its x, y part is "
                    "singular)");
    // Window depth at eye distance d is a + p[3][2]/d (a constant a): p[3][2] > 0 puts nearer
    // points at greater depth.
    const double depth_slope = p[3][2];
    const bool greater = depth_slope > 0.0;
    if (depth_slope == 0.0)
        throw Error("HostView: projection gives every point one depth (its [3][2] is 0)");
    if (greater != (host.depth == DepthConvention::ReverseZ))
        throw Error(std::string("HostView: projection puts nearer points at ") +
                    (greater ? "greater" : "smaller") + " depth, but depth is " +
                    (host.depth == DepthConvention::ReverseZ ? "ReverseZ" : "Standard/ZeroToOne") +
                    ": give the convention the host draws with");
    // The near plane: where window depth takes the near value (−1, 0 or 1 in NDC).
    const double near_ndc = host.depth == DepthConvention::Standard    ? -1.0
                            : host.depth == DepthConvention::ZeroToOne ? 0.0
                                                                       : 1.0;
    const double host_near = depth_slope / (near_ndc + p[2][2]);
    if (!(host_near > 0.0) || !std::isfinite(host_near))
        throw Error("HostView: projection's near plane is not in front of the eye (near " +
                    formatNumber(host_near) + " m)");

    // The LOD camera: the host's forward, no roll, a symmetric frustum through the host's
    // corners.
    const glm::dvec3 forward = world_from_eye * glm::dvec3(0.0, 0.0, -1.0);
    glm::dvec3 right = glm::cross(forward, glm::dvec3(0.0, 0.0, 1.0));
    if (glm::length(right) < 1e-9) // as lod::Camera does looking straight up or down
        right = glm::dvec3(1.0, 0.0, 0.0);
    right = glm::normalize(right);
    const glm::dvec3 up = glm::cross(right, forward);
    double tan_x = 0.0, tan_y = 0.0;
    for (const double sx : {-1.0, 1.0})
        for (const double sy : {-1.0, 1.0}) {
            // Eye depth 1 along forward: tangents are the lateral components.
            const glm::dvec3 d = world_from_eye * eyeDirection(p, sx, sy);
            tan_x = std::max(tan_x, std::abs(glm::dot(d, right)));
            tan_y = std::max(tan_y, std::abs(glm::dot(d, up)));
        }
    // γ of the host: the largest pixels per unit tangent, the 2x2 map's largest singular value.
    const double j00 = 0.5 * host.width * p[0][0], j01 = 0.5 * host.width * p[1][0];
    const double j10 = 0.5 * host.height * p[0][1], j11 = 0.5 * host.height * p[1][1];
    const double frobenius = j00 * j00 + j01 * j01 + j10 * j10 + j11 * j11;
    const double jdet = j00 * j11 - j01 * j10;
    const double sigma = std::sqrt(
        0.5 * (frobenius + std::sqrt(std::max(0.0, frobenius * frobenius - 4.0 * jdet * jdet))));
    // A viewport with that γ over the symmetric frustum (rounded up; the 1e-6 px keeps an
    // exact fit from growing by a pixel through rounding).
    const double lod_height = std::ceil(2.0 * sigma * tan_y - 1e-6);
    const double lod_width = std::ceil(lod_height * tan_x / tan_y - 1e-6);
    if (!(lod_height <= lod::kMaxViewportPixels && lod_width <= lod::kMaxViewportPixels) ||
        !(tan_y > 0.0 && tan_x > 0.0))
        throw Error("HostView: the projection's field of view and resolution (" +
                    std::to_string(host.width) + "x" + std::to_string(host.height) +
                    ") need LOD over more than " + std::to_string(lod::kMaxViewportPixels) +
                    " pixels across");
    const double fov_y_degrees = 2.0 * std::atan(tan_y) * 180.0 / std::numbers::pi;
    double near_m = 1.0, far_m = 1e6;
    renderer.clipPlanesFor(eye, near_m, far_m, exaggeration); // far: the whole terrain
    near_m = std::min(near_m, host_near); // culling never cuts what the host shows
    far_m = std::max(far_m, 2.0 * near_m);

    HostCamera out{lod::Camera(eye, eye + forward, fov_y_degrees, {int(lod_width), int(lod_height)},
                               near_m, far_m),
                   {},
                   {}};
    out.projection.view_projection = p * glm::dmat4(rotation);
    out.projection.zero_to_one = host.depth != DepthConvention::Standard;
    out.projection.greater = greater;
    out.rays = PixelRays{eye, world_from_eye, p, host.width, host.height};
    return out;
}

HostView hostViewOf(const lod::Camera& camera)
{
    HostView out;
    out.view = arrayOf(camera.view() * glm::translate(glm::dmat4(1.0), -camera.position()));
    out.projection = arrayOf(render::reverseZProjection(camera));
    out.width = camera.viewport().width;
    out.height = camera.viewport().height;
    out.depth = DepthConvention::ReverseZ;
    return out;
}

} // namespace ridge::api
