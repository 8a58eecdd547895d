#pragma once
// The reference ellipsoid of a globe terrain frame, and the geodetic ↔ Earth-centred,
// Earth-fixed (ECEF) conversions every globe computation goes through. Plain C++, double
// precision: the GPU never sees an Earth-scale coordinate (positions reach it relative to the
// camera, shaders/terrain_common.glsl's ellipsoidOffset, whose double twin is here).
//
//   X = (N + h) cos φ cos λ,  Y = (N + h) cos φ sin λ,  Z = (N (1 − e²) + h) sin φ,
//   N = a / √(1 − e² sin² φ)
//
// φ geodetic latitude, λ longitude (radians), h height above the ellipsoid along its normal.
#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

namespace ridge::lod {

struct Ellipsoid {
    double a = 6378137.0;           // semi-major axis, metres
    double f = 1.0 / 298.257223563; // flattening
    static Ellipsoid wgs84() { return {}; }
    double b() const { return a * (1.0 - f); }   // semi-minor axis
    double e2() const { return f * (2.0 - f); }  // first eccentricity squared
    double primeVertical(double latitude) const; // N(φ)
    // The largest radius of curvature anywhere on it: a²/b, at the poles.
    double maxCurvatureRadius() const { return a * a / b(); }
};

// Local east, north, up at (λ, φ): columns of the matrix that takes local vectors to ECEF.
struct EnuBasis {
    glm::dvec3 east{1.0, 0.0, 0.0};
    glm::dvec3 north{0.0, 1.0, 0.0};
    glm::dvec3 up{0.0, 0.0, 1.0};
    glm::dmat3 matrix() const { return glm::dmat3(east, north, up); }
};

struct Geodetic {
    double longitude = 0.0; // radians, (−π, π]
    double latitude = 0.0;  // radians, [−π/2, π/2]
    double height = 0.0;    // metres above the ellipsoid
};

// ECEF of a geodetic point. A latitude of exactly ±π/2 is the pole (X = Y = 0 whatever λ).
glm::dvec3 geodeticToEcef(const Ellipsoid& e, double longitude, double latitude, double height);
// The ellipsoid's outward normal at (λ, φ) (the geodetic up), unit.
glm::dvec3 geodeticUp(double longitude, double latitude);
EnuBasis enuBasis(double longitude, double latitude);
// Inverse of geodeticToEcef, to well under a micrometre for any point outside a 100 km ball
// around the centre (Bowring's start, Newton on the latitude); the centre itself maps to the
// north pole at height −b. Finite input only.
Geodetic ecefToGeodetic(const Ellipsoid& e, glm::dvec3 ecef);

// The GPU's precise form of P(λa + Δλ, φa + Δφ, ha + Δh) − P(λa, φa, ha): every term scales
// with the offsets, so float evaluation (terrain_common.glsl) keeps its relative precision
// near the anchor instead of losing metres to Earth-scale cancellation. Here in double, the
// same algebra, so tests can hold the shader to it.
glm::dvec3 ellipsoidOffset(const Ellipsoid& e, double anchor_longitude, double anchor_latitude,
                           double anchor_height, double d_longitude, double d_latitude,
                           double d_height);

} // namespace ridge::lod
