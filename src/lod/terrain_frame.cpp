#include "ridge/lod/terrain_frame.h"

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace ridge::lod {

namespace {

constexpr double kPi = std::numbers::pi;

// The box bounds the surface by sampling it no coarser than this (radians): the curved
// surface between samples is then within a sagitta of ~12 km (5°) of their hull, added to
// the box; fine patches (a few samples) need no more than their corners and centre.
constexpr double kMaxBoundStep = 5.0 * kPi / 180.0;

// {h · u : h in [h0, h1], u in [u0, u1]}.
void intervalProduct(double h0, double h1, double u0, double u1, double& lo, double& hi)
{
    const double p[4] = {h0 * u0, h0 * u1, h1 * u0, h1 * u1};
    lo = std::min(std::min(p[0], p[1]), std::min(p[2], p[3]));
    hi = std::max(std::max(p[0], p[1]), std::max(p[2], p[3]));
}

} // namespace

glm::dvec3 Box::centre() const
{
    const glm::dvec3 c = (min + max) * 0.5;
    return oriented ? origin + axes * c : c;
}

glm::dvec3 Box::toLocal(glm::dvec3 world) const
{
    return oriented ? glm::transpose(axes) * (world - origin) : world;
}

glm::dvec3 Box::directionToLocal(glm::dvec3 world) const
{
    return oriented ? glm::transpose(axes) * world : world;
}

std::string_view surfaceName(Surface s)
{
    return s == Surface::Ellipsoid ? "ellipsoid" : "plane";
}

TerrainFrame TerrainFrame::ellipsoid(const PyramidGeometry& geometry, double spacing_x,
                                     double spacing_y, const GeodeticGrid& grid)
{
    TerrainFrame f(geometry, spacing_x, spacing_y);
    f.surface_ = Surface::Ellipsoid;
    f.grid_ = grid;
    return f;
}

TerrainFrame TerrainFrame::projected(const PyramidGeometry& geometry, double spacing_x,
                                     double spacing_y, std::shared_ptr<const ProjectedGrid> grid)
{
    TerrainFrame f(geometry, spacing_x, spacing_y);
    f.surface_ = Surface::Ellipsoid;
    f.grid_.ellipsoid = grid->ellipsoid();
    f.projected_ = std::move(grid);
    return f;
}

double TerrainFrame::columnAngle() const
{
    if (!projected_)
        return grid_.dlon;
    // Ground metres over the smallest radius of curvature (b²/a) bound the angle the surface
    // turns through; the sagitta formulas then stay bounds (lod/ellipsoid.h).
    const Ellipsoid& e = grid_.ellipsoid;
    return projected_->columnMetresBound() * e.a / (e.b() * e.b());
}

double TerrainFrame::rowAngle() const
{
    if (!projected_)
        return std::abs(grid_.dlat);
    const Ellipsoid& e = grid_.ellipsoid;
    return projected_->rowMetresBound() * e.a / (e.b() * e.b());
}

double TerrainFrame::latitudeOf(double row) const
{
    return std::clamp(grid_.lat0 + row * grid_.dlat, -kPi / 2, kPi / 2);
}

bool TerrainFrame::poleRow(double row) const
{
    if (!onEllipsoid() || projected_)
        return false;
    return std::abs(grid_.lat0 + row * grid_.dlat) >= kPi / 2 - 1e-6 * std::abs(grid_.dlat);
}

glm::dvec3 TerrainFrame::worldOf(double column, double row, double height) const
{
    if (!onEllipsoid())
        return {xOf(column), yOf(row), height};
    if (projected_) {
        const glm::dvec3 s = projected_->surfaceAt(column, row);
        return s + height * projected_->normalThrough(s);
    }
    const double lat =
        poleRow(row) ? std::copysign(kPi / 2, grid_.lat0 + row * grid_.dlat) : latitudeOf(row);
    return geodeticToEcef(grid_.ellipsoid, longitudeOf(column), lat, height);
}

glm::dvec3 TerrainFrame::upAt(double column, double row) const
{
    return basisAt(column, row).up;
}

EnuBasis TerrainFrame::basisAt(double column, double row) const
{
    if (!onEllipsoid())
        return {};
    if (projected_) {
        EnuBasis b;
        b.up = projected_->normalThrough(projected_->surfaceAt(column, row));
        const glm::dvec3 east = glm::cross(glm::dvec3(0.0, 0.0, 1.0), b.up);
        b.east = glm::dot(east, east) > 1e-24 ? glm::normalize(east) : glm::dvec3(1.0, 0.0, 0.0);
        b.north = glm::cross(b.up, b.east);
        return b;
    }
    const double lat =
        poleRow(row) ? std::copysign(kPi / 2, grid_.lat0 + row * grid_.dlat) : latitudeOf(row);
    return enuBasis(longitudeOf(column), lat);
}

glm::dvec3 TerrainFrame::gridOf(glm::dvec3 world) const
{
    if (!onEllipsoid())
        return {columnOf(world.x), rowOf(world.y), world.z};
    const Geodetic g = ecefToGeodetic(grid_.ellipsoid, world);
    if (projected_) {
        const glm::dvec2 q = projected_->gridOf(world);
        return {q.x, q.y, g.height};
    }
    double column = (g.longitude - grid_.lon0) / grid_.dlon;
    const double period = 2.0 * kPi / grid_.dlon;
    if (grid_.wrap_columns > 0) {
        const double w = double(grid_.wrap_columns);
        column -= w * std::floor((column + 0.5) / w);
    } else {
        const double centre = 0.5 * (geometry_.width() - 1);
        column -= period * std::round((column - centre) / period);
    }
    return {column, (g.latitude - grid_.lat0) / grid_.dlat, g.height};
}

namespace {

// (1 − cos(θ/2)) for an arc θ ≥ 0, the chord's sagitta per unit radius; θ beyond a half turn
// is taken as one (a chord cannot sag more than the radius).
double sagPerRadius(double theta)
{
    const double s = std::sin(0.5 * std::min(theta, std::numbers::pi) * 0.5);
    return 2.0 * s * s;
}

} // namespace

double TerrainFrame::chordSag(double samples) const
{
    if (!onEllipsoid())
        return 0.0;
    return 1.01 * grid_.ellipsoid.maxCurvatureRadius() *
           (sagPerRadius(samples * columnAngle()) + sagPerRadius(samples * rowAngle()));
}

double TerrainFrame::edgeSag(double samples) const
{
    if (!onEllipsoid())
        return 0.0;
    return 1.01 * grid_.ellipsoid.maxCurvatureRadius() *
           sagPerRadius(samples * std::max(columnAngle(), rowAngle()));
}

glm::dvec3 TerrainFrame::upThrough(glm::dvec3 world) const
{
    if (!onEllipsoid())
        return {0.0, 0.0, 1.0};
    const Geodetic g = ecefToGeodetic(grid_.ellipsoid, world);
    return geodeticUp(g.longitude, g.latitude);
}

Box TerrainFrame::patchBox(PatchId p, double min_z, double max_z) const
{
    if (onEllipsoid())
        return ellipsoidPatchBox(p, min_z, max_z);
    const double span = double(geometry_.cells()) * double(geometry_.step(p.level));
    const double c0 = p.x * span, c1 = std::min(c0 + span, double(geometry_.width() - 1));
    const double r0 = p.y * span, r1 = std::min(r0 + span, double(geometry_.height() - 1));
    // Rows grow southwards and y northwards: the last row is the box's south side.
    return Box{{xOf(c0), yOf(r1), min_z}, {xOf(c1), yOf(r0), max_z}};
}

Box TerrainFrame::ellipsoidPatchBox(PatchId p, double min_z, double max_z) const
{
    const double span = double(geometry_.cells()) * double(geometry_.step(p.level));
    const double c0 = p.x * span, c1 = std::min(c0 + span, double(geometry_.width() - 1));
    const double r0 = p.y * span, r1 = std::min(r0 + span, double(geometry_.height() - 1));
    const double cm = 0.5 * (c0 + c1), rm = 0.5 * (r0 + r1);
    Box box;
    box.oriented = true;
    box.origin = worldOf(cm, rm, 0.0);
    box.axes = basisAt(cm, rm).matrix();

    // The surface at height 0: the hull of a grid of its points, plus the sagitta of the
    // ellipsoid between them — for a bilinear patch of points on it, at most
    // (Δλ² + Δφ²)/8 times its largest radius of curvature (the cross term is bilinear).
    const double lon_span = (c1 - c0) * columnAngle(), lat_span = (r1 - r0) * rowAngle();
    const int nu = std::max(2, int(std::ceil(lon_span / kMaxBoundStep)));
    const int nv = std::max(2, int(std::ceil(lat_span / kMaxBoundStep)));
    glm::dvec3 lo(INFINITY), hi(-INFINITY);
    for (int j = 0; j <= nv; ++j)
        for (int i = 0; i <= nu; ++i) {
            const double c = c0 + (c1 - c0) * i / nu, r = r0 + (r1 - r0) * j / nv;
            const glm::dvec3 q = box.toLocal(worldOf(c, r, 0.0));
            lo = glm::min(lo, q);
            hi = glm::max(hi, q);
        }
    const double du = lon_span / nu, dv = lat_span / nv;
    const double sag = grid_.ellipsoid.maxCurvatureRadius() * (du * du + dv * dv) / 8.0;
    lo -= glm::dvec3(sag);
    hi += glm::dvec3(sag);

    // Heights along the local up, which turns by at most α from the centre's: half the
    // latitude span plus half the longitude span (moving along a parallel turns it less).
    const double alpha = std::min(kPi, 0.5 * lat_span + 0.5 * lon_span);
    const double s = alpha >= kPi / 2 ? 1.0 : std::sin(alpha);
    const glm::dvec3 up_lo(-s, -s, std::cos(alpha)), up_hi(s, s, 1.0);
    for (int k = 0; k < 3; ++k) {
        double a, b;
        intervalProduct(min_z, max_z, up_lo[k], up_hi[k], a, b);
        box.min[k] = lo[k] + a;
        box.max[k] = hi[k] + b;
    }
    return box;
}

} // namespace ridge::lod
