#include "ridge/lod/hemisphere_normals.h"

#include "error_expectations.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <vector>

using namespace ridge;
using namespace ridge::lod;
using ridge::test::expectError;

namespace {

constexpr double kDegrees = 180.0 / M_PI;
constexpr HemisphereMap kMaps[] = {HemisphereMap::Orthographic, HemisphereMap::Concentric};

const char* nameOf(HemisphereMap map)
{
    return map == HemisphereMap::Orthographic ? "orthographic" : "concentric";
}

double angleDegrees(glm::dvec3 a, glm::dvec3 b)
{
    // atan2 of |a×b| and a·b: accurate for tiny angles, unlike acos.
    const glm::dvec3 c(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
    return std::atan2(std::sqrt(c.x * c.x + c.y * c.y + c.z * c.z),
                      a.x * b.x + a.y * b.y + a.z * b.z) *
           kDegrees;
}

// Unit normals uniformly distributed (by area) over the cap of zenith angles [0, max_zenith].
std::vector<glm::dvec3> capNormals(int count, double max_zenith_degrees, uint32_t seed)
{
    std::mt19937 rng(seed);
    const double z_min = std::cos(max_zenith_degrees / kDegrees);
    std::uniform_real_distribution<double> z(z_min, 1.0), phi(0.0, 2 * M_PI);
    std::vector<glm::dvec3> normals(count);
    for (glm::dvec3& n : normals) {
        const double zz = z(rng), r = std::sqrt(std::max(0.0, 1 - zz * zz)), p = phi(rng);
        n = {r * std::cos(p), r * std::sin(p), zz};
    }
    return normals;
}

glm::dvec3 textureNormal(const std::vector<uint8_t>& texture, NormalIndex index)
{
    const uint8_t* t = &texture[4 * (size_t(index.v) * kHemisphereTextureSize + index.u)];
    const glm::dvec3 n(2.0 * t[0] / 255 - 1, 2.0 * t[1] / 255 - 1, 2.0 * t[2] / 255 - 1);
    return n / std::sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
}

struct ErrorStats {
    double max = 0, mean = 0, worst_zenith = 0; // through the exact decode
    double texture_max = 0, texture_mean = 0;   // through the RGBA8 texture
    double band_max[4] = {0, 0, 0, 0};          // zenith 0–30°, 30–60°, 60–80°, 80–90°
};

ErrorStats measure(HemisphereMap map, const std::vector<glm::dvec3>& normals)
{
    const std::vector<uint8_t> texture = buildHemisphereNormalTexture(map);
    ErrorStats s;
    for (const glm::dvec3& n : normals) {
        const NormalIndex index = encodeHemisphereNormal(map, glm::vec3(n));
        const double e = angleDegrees(n, glm::dvec3(decodeHemisphereNormal(map, index.u, index.v)));
        const double te = angleDegrees(n, textureNormal(texture, index));
        const double zenith = std::acos(std::min(1.0, n.z)) * kDegrees;
        if (e > s.max)
            s.max = e, s.worst_zenith = zenith;
        s.mean += e / normals.size();
        s.texture_max = std::max(s.texture_max, te);
        s.texture_mean += te / normals.size();
        const int band = zenith < 30 ? 0 : zenith < 60 ? 1 : zenith < 80 ? 2 : 3;
        s.band_max[band] = std::max(s.band_max[band], e);
    }
    return s;
}

void print(const char* set, HemisphereMap map, const ErrorStats& s)
{
    std::printf("%-12s %-22s max %.3f° (at zenith %.1f°) mean %.4f° | via RGBA8 texture max %.3f° "
                "mean %.4f° | band max 0-30° %.3f, 30-60° %.3f, 60-80° %.3f, 80-90° %.3f\n",
                nameOf(map), set, s.max, s.worst_zenith, s.mean, s.texture_max, s.texture_mean,
                s.band_max[0], s.band_max[1], s.band_max[2], s.band_max[3]);
}

} // namespace

TEST(HemisphereNormals, EveryTexelDecodesToAnUpwardUnitNormal)
{
    for (HemisphereMap map : kMaps)
        for (int v = 0; v < 256; ++v)
            for (int u = 0; u < 256; ++u) {
                const glm::vec3 n = decodeHemisphereNormal(map, uint8_t(u), uint8_t(v));
                ASSERT_NEAR(n.x * n.x + n.y * n.y + n.z * n.z, 1.0, 1e-6) << u << " " << v;
                ASSERT_GE(n.z, 0.0f);
            }
}

TEST(HemisphereNormals, TexelCentresEncodeToThemselves)
{
    for (HemisphereMap map : kMaps) {
        int checked = 0;
        for (int v = 0; v < 256; ++v)
            for (int u = 0; u < 256; ++u) {
                const glm::vec3 n = decodeHemisphereNormal(map, uint8_t(u), uint8_t(v));
                if (n.z == 0.0f) // orthographic corners outside the disk: horizon, not invertible
                    continue;
                const NormalIndex back = encodeHemisphereNormal(map, n);
                ASSERT_EQ(back.u, u) << nameOf(map) << " " << u << " " << v;
                ASSERT_EQ(back.v, v) << nameOf(map) << " " << u << " " << v;
                ++checked;
            }
        // The orthographic map uses only the texels inside its disk, ~π/4 of them.
        if (map == HemisphereMap::Orthographic)
            EXPECT_NEAR(checked / 65536.0, M_PI / 4, 0.01);
        else
            EXPECT_EQ(checked, 65536);
    }
}

// The paper's reason to interpolate normal indices: the parameterisation has no singularity,
// so texels next to each other hold nearby normals, and they are nearer still where terrain
// normals are.
TEST(HemisphereNormals, NeighbouringTexelsHoldNearbyNormals)
{
    for (HemisphereMap map : kMaps) {
        double worst = 0, worst_terrain = 0;
        for (int v = 0; v < 256; ++v)
            for (int u = 0; u < 256; ++u) {
                const glm::dvec3 n(decodeHemisphereNormal(map, uint8_t(u), uint8_t(v)));
                for (auto [du, dv] : {std::pair{1, 0}, {0, 1}}) {
                    if (u + du > 255 || v + dv > 255)
                        continue;
                    const glm::dvec3 m(
                        decodeHemisphereNormal(map, uint8_t(u + du), uint8_t(v + dv)));
                    if (n.z == 0 && m.z == 0)
                        continue; // both outside the orthographic disk
                    const double a = angleDegrees(n, m);
                    worst = std::max(worst, a);
                    if (n.z >= 0.5 && m.z >= 0.5)
                        worst_terrain = std::max(worst_terrain, a);
                }
            }
        std::printf("%-12s neighbouring texels: max %.3f° apart, %.3f° within 60° of vertical\n",
                    nameOf(map), worst, worst_terrain);
        EXPECT_LT(worst, 9.0) << nameOf(map);         // measured 7.09° / 3.73°
        EXPECT_LT(worst_terrain, 1.2) << nameOf(map); // 0.88° / 0.94°
    }
}

// "Show the difference": the round-trip angular error of both maps over the whole hemisphere
// and over terrain-like normals (within 60° of vertical), 100k each. Bounds: the measured
// figures (printed, and noted orthographic / concentric beside each bound) with ~25% margin.
TEST(HemisphereNormals, RoundTripErrorsOfBothMaps)
{
    const std::vector<glm::dvec3> hemisphere = capNormals(100000, 90.0, 1);
    const std::vector<glm::dvec3> terrain = capNormals(100000, 60.0, 2);
    for (HemisphereMap map : kMaps) {
        const ErrorStats all = measure(map, hemisphere), steep = measure(map, terrain);
        print("uniform hemisphere", map, all);
        print("within 60° of vertical", map, steep);
        // Both are worst at the horizon, where dz/dr of the orthographic lift is unbounded
        // (one texel of r spans ~5° of zenith there). The concentric map's outermost ring of
        // texel centres sits at r = 255/256, zenith 84.9°, so every steeper normal (8.7% of the
        // uniform hemisphere) rounds to it: its hemisphere mean is worse than the orthographic
        // map's, whose rim texels straddle the circle; within 60° its finer angular cells
        // (π/4 of the orthographic ones) make it slightly better.
        const bool ortho = map == HemisphereMap::Orthographic;
        EXPECT_GT(all.worst_zenith, 80.0) << nameOf(map);
        EXPECT_LT(all.max, 6.5) << nameOf(map);                  // measured 4.99° / 5.07°
        EXPECT_LT(all.mean, ortho ? 0.45 : 0.65) << nameOf(map); // 0.344° / 0.517°
        EXPECT_LT(steep.max, 0.6) << nameOf(map);                // 0.477° / 0.466°
        EXPECT_LT(steep.mean, 0.25) << nameOf(map);              // 0.202° / 0.190°
        EXPECT_LT(steep.texture_max, 1.0) << nameOf(map);        // 0.722° / 0.803°
    }
}

TEST(HemisphereNormals, TextureIsRGBA8OfTheDecodedNormals)
{
    for (HemisphereMap map : kMaps) {
        const std::vector<uint8_t> texture = buildHemisphereNormalTexture(map);
        ASSERT_EQ(texture.size(), 256u * 256 * 4);
        for (int v = 0; v < 256; v += 3)
            for (int u = 0; u < 256; u += 5) {
                const NormalIndex index{uint8_t(u), uint8_t(v)};
                ASSERT_EQ(texture[4 * (size_t(v) * 256 + u) + 3], 255);
                const glm::dvec3 exact(decodeHemisphereNormal(map, index.u, index.v));
                ASSERT_LT(angleDegrees(exact, textureNormal(texture, index)), 0.5) << u << " " << v;
            }
    }
}

TEST(HemisphereNormals, EncodeRefusesNormalsThatAreNotUpwardDirections)
{
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    for (HemisphereMap map : kMaps) {
        expectError([&] { encodeHemisphereNormal(map, {nan, 0, 1}); }, "normal is (nan");
        expectError([&] { encodeHemisphereNormal(map, {0, inf, 1}); }, "normal is (0, inf");
        expectError([&] { encodeHemisphereNormal(map, {0, 0, 0}); }, "must have a direction");
        expectError([&] { encodeHemisphereNormal(map, {0, 0.6f, -0.8f}); }, "z >= 0");
        // Not unit length is fine; the horizon is the hemisphere's edge, still valid.
        const NormalIndex up = encodeHemisphereNormal(map, {0, 0, 5});
        EXPECT_TRUE(up.u == 127 || up.u == 128) << int(up.u);
        EXPECT_TRUE(up.v == 127 || up.v == 128) << int(up.v);
        EXPECT_NO_THROW(encodeHemisphereNormal(map, {1, 0, 0}));
    }
    expectError([] { decodeHemisphereNormal(HemisphereMap(7), 0, 0); }, "not a HemisphereMap");
}
