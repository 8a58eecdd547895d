#include "ridge/lod/ellipsoid.h"

#include <glm/geometric.hpp>

#include <cmath>
#include <numbers>

namespace ridge::lod {

namespace {

// Exactly 0 and ±1 at the poles: sin/cos of ±π/2 in double are 1 and 6e-17, and that 6e-17
// times N would put every vertex of a pole row 0.4 nm apart, on different sides of the axis.
void sinCosLatitude(double latitude, double& s, double& c)
{
    if (latitude >= std::numbers::pi / 2) {
        s = 1.0;
        c = 0.0;
    } else if (latitude <= -std::numbers::pi / 2) {
        s = -1.0;
        c = 0.0;
    } else {
        s = std::sin(latitude);
        c = std::cos(latitude);
    }
}

} // namespace

double Ellipsoid::primeVertical(double latitude) const
{
    const double s = std::sin(latitude);
    return a / std::sqrt(1.0 - e2() * s * s);
}

glm::dvec3 geodeticToEcef(const Ellipsoid& e, double longitude, double latitude, double height)
{
    double s, c;
    sinCosLatitude(latitude, s, c);
    const double n = e.a / std::sqrt(1.0 - e.e2() * s * s);
    const double r = (n + height) * c;
    return {r * std::cos(longitude), r * std::sin(longitude), (n * (1.0 - e.e2()) + height) * s};
}

glm::dvec3 geodeticUp(double longitude, double latitude)
{
    double s, c;
    sinCosLatitude(latitude, s, c);
    return {c * std::cos(longitude), c * std::sin(longitude), s};
}

EnuBasis enuBasis(double longitude, double latitude)
{
    double s, c;
    sinCosLatitude(latitude, s, c);
    const double sl = std::sin(longitude), cl = std::cos(longitude);
    EnuBasis b;
    b.east = {-sl, cl, 0.0};
    b.north = {-s * cl, -s * sl, c};
    b.up = {c * cl, c * sl, s};
    return b;
}

Geodetic ecefToGeodetic(const Ellipsoid& e, glm::dvec3 p)
{
    const double e2 = e.e2(), b = e.b();
    const double rho = std::hypot(p.x, p.y);
    Geodetic g;
    g.longitude = rho > 0.0 ? std::atan2(p.y, p.x) : 0.0;
    if (rho == 0.0) {
        g.latitude = p.z >= 0.0 ? std::numbers::pi / 2 : -std::numbers::pi / 2;
        g.height = std::abs(p.z) - b;
        return g;
    }
    // Bowring's parametric start, then Newton steps on f(φ) = ρ sin φ − z cos φ − e² N sin φ cos φ
    // written through the height: two or three steps reach double precision.
    const double ep2 = e2 / (1.0 - e2);
    double beta = std::atan2(p.z * e.a, rho * b);
    double phi = std::atan2(p.z + ep2 * b * std::pow(std::sin(beta), 3),
                            rho - e2 * e.a * std::pow(std::cos(beta), 3));
    for (int i = 0; i < 4; ++i) {
        const double s = std::sin(phi);
        const double n = e.a / std::sqrt(1.0 - e2 * s * s);
        // tan φ = (z + e² N sin φ) / ρ
        const double next = std::atan2(p.z + e2 * n * s, rho);
        if (next == phi)
            break;
        phi = next;
    }
    const double s = std::sin(phi), c = std::cos(phi);
    const double n = e.a / std::sqrt(1.0 - e2 * s * s);
    g.latitude = phi;
    // The better conditioned of the two height formulas for this latitude.
    g.height = std::abs(c) > 0.5 ? rho / c - n : p.z / s - n * (1.0 - e2);
    return g;
}

glm::dvec3 ellipsoidOffset(const Ellipsoid& e, double lambda_a, double phi_a, double h_a,
                           double d_lambda, double d_phi, double d_h)
{
    const double e2 = e.e2();
    const double cpa = std::cos(phi_a), spa = std::sin(phi_a);
    const double cla = std::cos(lambda_a), sla = std::sin(lambda_a);
    // cos x − 1 = −2 sin²(x/2): no cancellation for small offsets.
    const double hp = std::sin(0.5 * d_phi), hl = std::sin(0.5 * d_lambda);
    const double cp1 = -2.0 * hp * hp, sp = std::sin(d_phi);
    const double cl1 = -2.0 * hl * hl, sl = std::sin(d_lambda);
    const double d_cos_phi = cpa * cp1 - spa * sp; // cos φ − cos φa
    const double d_sin_phi = spa * cp1 + cpa * sp; // sin φ − sin φa
    const double d_cos_l = cla * cl1 - sla * sl;
    const double d_sin_l = sla * cl1 + cla * sl;
    const double cos_phi = cpa + d_cos_phi, sin_phi = spa + d_sin_phi;
    const double w_a = 1.0 - e2 * spa * spa;
    const double d_w = -e2 * d_sin_phi * (sin_phi + spa); // w − w_a
    const double w = w_a + d_w;
    const double sw = std::sqrt(w), swa = std::sqrt(w_a);
    const double d_n = e.a * -d_w / (sw * swa * (sw + swa)); // N − N_a
    const double n_a = e.a / swa;
    const double r_a = n_a + h_a; // (N + h) at the anchor
    const double u_a = r_a * cpa; // distance from the axis at the anchor
    const double d_u = (d_n + d_h) * cos_phi + r_a * d_cos_phi;
    const double d_z = (d_n * (1.0 - e2) + d_h) * sin_phi + (n_a * (1.0 - e2) + h_a) * d_sin_phi;
    return {d_u * (cla + d_cos_l) + u_a * d_cos_l, d_u * (sla + d_sin_l) + u_a * d_sin_l, d_z};
}

} // namespace ridge::lod
