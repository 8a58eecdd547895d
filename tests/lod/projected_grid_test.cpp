// The lattice that carries a projected grid onto the ellipsoid (lod/projected_grid.h), held
// to the map it samples: an azimuthal equidistant grid centred on the North Pole (the pole an
// interior point, where longitude is singular but S is smooth), so that every point of the
// surface, its inverse and its refinement can be checked against the exact map. PROJ's own
// maps are checked in archive_frame_test.cpp.
#include "error_expectations.h"

#include "ridge/lod/projected_grid.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

namespace ridge::lod {
namespace {

constexpr double kPi = std::numbers::pi;

// 201 x 201 samples 5 km apart around the North Pole (sample (100, 100)): longitude from
// the direction, latitude from the distance on a sphere of the semi-major axis.
std::optional<std::array<double, 2>> polarGrid(double c, double r)
{
    const double x = (c - 100.0) * 5000.0, y = (100.0 - r) * 5000.0;
    const double rho = std::hypot(x, y);
    return std::array<double, 2>{std::atan2(x, -y), kPi / 2 - rho / Ellipsoid::wgs84().a};
}

LatticeRequest polarRequest()
{
    LatticeRequest q;
    q.columns_end = q.rows_end = 256.0; // a pyramid's padding beyond the 201 samples
    q.last_column = q.last_row = 200.0;
    return q;
}

glm::dvec3 exactPoint(double c, double r)
{
    const std::array<double, 2> g = *polarGrid(c, r);
    return geodeticToEcef(Ellipsoid::wgs84(), g[0], g[1], 0.0);
}

TEST(ProjectedGrid, HermiteWeightsInterpolateValuesAndDerivatives)
{
    const std::array<double, 4> w0 = hermiteWeights(0.0), w1 = hermiteWeights(1.0);
    EXPECT_EQ(w0, (std::array<double, 4>{1.0, 0.0, 0.0, 0.0}));
    EXPECT_EQ(w1, (std::array<double, 4>{0.0, 1.0, 0.0, 0.0}));
    const std::array<double, 4> d0 = hermiteWeights(0.0, true), d1 = hermiteWeights(1.0, true);
    EXPECT_EQ(d0, (std::array<double, 4>{0.0, 0.0, 1.0, 0.0}));
    EXPECT_EQ(d1, (std::array<double, 4>{0.0, 0.0, 0.0, 1.0}));
    // A cubic is reproduced exactly: f(u) = u³ − 2u + 1 from f(0), f(1), f'(0), f'(1).
    for (double u : {0.1, 0.37, 0.5, 0.9}) {
        const std::array<double, 4> w = hermiteWeights(u);
        EXPECT_NEAR(w[0] * 1.0 + w[1] * 0.0 + w[2] * -2.0 + w[3] * 1.0, u * u * u - 2 * u + 1,
                    1e-15);
    }
}

TEST(ProjectedGrid, TheSurfaceIsTheMapToAMillimetreThroughThePole)
{
    const ProjectedGrid g = ProjectedGrid::build(Ellipsoid::wgs84(), polarRequest(), polarGrid);
    EXPECT_LE(g.measuredError(), 1e-3);
    // One node before sample 0 to at least one beyond the padding.
    EXPECT_EQ(g.firstColumn(), -g.step());
    EXPECT_GE(g.firstColumn() + (g.nodesX() - 1) * g.step(), 256);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> in(0.0, 200.0);
    double worst = 0.0;
    for (int k = 0; k < 2000; ++k) {
        const double c = k == 0 ? 100.0 : in(rng), r = k == 0 ? 100.0 : in(rng);
        worst = std::max(worst, glm::length(g.surfaceAt(c, r) - exactPoint(c, r)));
        // The inverse finds the sample again, at the pole too.
        const glm::dvec2 q =
            g.gridOf(exactPoint(c, r) + 1234.0 * g.normalThrough(exactPoint(c, r)));
        EXPECT_NEAR(q.x, c, 1e-4);
        EXPECT_NEAR(q.y, r, 1e-4);
    }
    EXPECT_LT(worst, 1.5e-3);
    // Ground metres per column bounded, tightly (+1%): 5 km on the map's sphere of radius a
    // are a little more on the ellipsoid, whose radius of curvature at the pole is a²/b.
    double widest = 0.0;
    for (int k = 0; k < 200; ++k) {
        const double c = in(rng), r = in(rng);
        widest =
            std::max(widest, glm::length(exactPoint(c + 1e-3, r) - exactPoint(c - 1e-3, r)) / 2e-3);
    }
    EXPECT_GE(g.columnMetresBound(), widest);
    EXPECT_LE(g.columnMetresBound(), 1.02 * widest);
    // Tangents are the map's derivatives (central differences of the exact map).
    glm::dvec3 s_c, s_r;
    g.tangentsAt(37.3, 151.8, s_c, s_r);
    const glm::dvec3 e_c = (exactPoint(37.3 + 1e-3, 151.8) - exactPoint(37.3 - 1e-3, 151.8)) / 2e-3;
    EXPECT_LT(glm::length(s_c - e_c), 1e-3 * glm::length(e_c));
    const glm::dvec3 e_r = (exactPoint(37.3, 151.8 + 1e-3) - exactPoint(37.3, 151.8 - 1e-3)) / 2e-3;
    EXPECT_LT(glm::length(s_r - e_r), 1e-3 * glm::length(e_r));
}

TEST(ProjectedGrid, ATighterToleranceRefinesTheLattice)
{
    LatticeRequest loose = polarRequest();
    loose.tolerance = 1e3;
    LatticeRequest tight = polarRequest();
    tight.tolerance = 1e-4;
    const ProjectedGrid a = ProjectedGrid::build(Ellipsoid::wgs84(), loose, polarGrid);
    const ProjectedGrid b = ProjectedGrid::build(Ellipsoid::wgs84(), tight, polarGrid);
    EXPECT_LT(b.step(), a.step());
    EXPECT_LE(b.measuredError(), 1e-4);
    EXPECT_GT(a.measuredError(), b.measuredError());
}

TEST(ProjectedGrid, OnlyNodesBeyondTheRasterMayLackAPoint)
{
    // A projection that stops 20 samples past the raster: the padding's nodes continue the
    // nearest reached node's tangent plane, and the raster keeps its millimetre.
    auto stops = [](double c, double r) -> std::optional<std::array<double, 2>> {
        if (c > 240.0 || r > 240.0)
            return std::nullopt;
        return polarGrid(c, r);
    };
    const ProjectedGrid g = ProjectedGrid::build(Ellipsoid::wgs84(), polarRequest(), stops);
    EXPECT_LE(g.measuredError(), 1e-3);
    const glm::dvec3 far = g.surfaceAt(256.0, 256.0);
    EXPECT_TRUE(std::isfinite(far.x) && std::isfinite(far.y) && std::isfinite(far.z));

    // One that does not reach the raster itself is refused, naming where.
    auto hole = [](double c, double r) -> std::optional<std::array<double, 2>> {
        if (c > 60.0 && c < 70.0 && r > 60.0 && r < 70.0)
            return std::nullopt;
        return polarGrid(c, r);
    };
    test::expectError([&] { ProjectedGrid::build(Ellipsoid::wgs84(), polarRequest(), hole); },
                      "has no point at grid column");
}

} // namespace
} // namespace ridge::lod
