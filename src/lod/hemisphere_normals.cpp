// Orthographic and concentric (Shirley & Chiu) hemisphere normal textures; see the header.
#include "ridge/lod/hemisphere_normals.h"

#include "ridge/core/error.h"
#include "ridge/core/parameter_check.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace ridge::lod {
namespace {

constexpr double kQuarterPi = std::numbers::pi / 4;

struct Vec2 {
    double x, y;
};
struct Vec3 {
    double x, y, z;
};

void checkMap(HemisphereMap map)
{
    if (map != HemisphereMap::Orthographic && map != HemisphereMap::Concentric)
        throw Error("map is not a HemisphereMap value");
}

// Texel index → square coordinate of its centre, in (−1, 1).
double centre(int index)
{
    return (2.0 * index + 1.0) / kHemisphereTextureSize - 1.0;
}

// Square coordinate → the texel that contains it.
int texelOf(double a)
{
    const int index = int(std::floor((a + 1.0) * 0.5 * kHemisphereTextureSize));
    return std::clamp(index, 0, kHemisphereTextureSize - 1);
}

// Shirley & Chiu's concentric map, square (a, b) ∈ [−1, 1]² → unit disk, with Cline's
// single-branch form: concentric squares go to concentric circles, area fractions kept.
Vec2 squareToDisk(double a, double b)
{
    if (a == 0.0 && b == 0.0)
        return {0.0, 0.0};
    double r, phi;
    if (std::abs(a) > std::abs(b))
        r = a, phi = kQuarterPi * (b / a);
    else
        r = b, phi = 2 * kQuarterPi - kQuarterPi * (a / b);
    return {r * std::cos(phi), r * std::sin(phi)};
}

// Its inverse: the disk (x, y) → square, by the octant of the angle.
Vec2 diskToSquare(double x, double y)
{
    const double r = std::hypot(x, y);
    if (r == 0.0)
        return {0.0, 0.0};
    double phi = std::atan2(y, x); // (−π, π]
    if (phi < -kQuarterPi)
        phi += 8 * kQuarterPi; // [−π/4, 7π/4)
    if (phi < kQuarterPi)
        return {r, phi * r / kQuarterPi};
    if (phi < 3 * kQuarterPi)
        return {-(phi - 2 * kQuarterPi) * r / kQuarterPi, r};
    if (phi < 5 * kQuarterPi)
        return {-r, -(phi - 4 * kQuarterPi) * r / kQuarterPi};
    return {(phi - 6 * kQuarterPi) * r / kQuarterPi, -r};
}

// Disk point lifted straight up onto the hemisphere; outside the disk (orthographic corners)
// the nearest horizon direction.
Vec3 liftOrthographic(double x, double y)
{
    const double r2 = x * x + y * y;
    if (r2 >= 1.0) {
        const double r = std::sqrt(r2);
        return {x / r, y / r, 0.0};
    }
    return {x, y, std::sqrt(1.0 - r2)};
}

Vec3 decodeDouble(HemisphereMap map, int u, int v)
{
    const double a = centre(u), b = centre(v);
    if (map == HemisphereMap::Orthographic)
        return liftOrthographic(a, b);
    const Vec2 disk = squareToDisk(a, b);
    return liftOrthographic(disk.x, disk.y);
}

} // namespace

NormalIndex encodeHemisphereNormal(HemisphereMap map, glm::vec3 normal)
{
    checkMap(map);
    const double values[3] = {normal.x, normal.y, normal.z};
    checkParameters("normal", values, 3, ValueRange::any());
    const double length =
        std::sqrt(values[0] * values[0] + values[1] * values[1] + values[2] * values[2]);
    if (!(length > 0.0))
        throw Error("normal is (0, 0, 0): must have a direction");
    if (normal.z < 0.0f)
        throw Error("normal has z = " + formatNumber(normal.z) +
                    " < 0: hemisphere normals point up (z >= 0)");
    const Vec3 n{values[0] / length, values[1] / length, values[2] / length};
    const Vec2 square =
        map == HemisphereMap::Orthographic ? Vec2{n.x, n.y} : diskToSquare(n.x, n.y);
    // The containing texel is the nearest centre in the square, not always in angle (near the
    // horizon one texel spans degrees of elevation, and in the concentric map cells are
    // sheared): the best of its 3×3 neighbourhood wins.
    const int u0 = texelOf(square.x), v0 = texelOf(square.y);
    NormalIndex best{uint8_t(u0), uint8_t(v0)};
    double best_dot = -2.0;
    for (int v = std::max(v0 - 1, 0); v <= std::min(v0 + 1, kHemisphereTextureSize - 1); ++v)
        for (int u = std::max(u0 - 1, 0); u <= std::min(u0 + 1, kHemisphereTextureSize - 1); ++u) {
            const Vec3 d = decodeDouble(map, u, v);
            const double dot = d.x * n.x + d.y * n.y + d.z * n.z;
            if (dot > best_dot)
                best_dot = dot, best = {uint8_t(u), uint8_t(v)};
        }
    return best;
}

glm::vec3 decodeHemisphereNormal(HemisphereMap map, uint8_t u, uint8_t v)
{
    checkMap(map);
    const Vec3 d = decodeDouble(map, u, v);
    return {float(d.x), float(d.y), float(d.z)};
}

std::vector<uint8_t> buildHemisphereNormalTexture(HemisphereMap map)
{
    checkMap(map);
    constexpr int size = kHemisphereTextureSize;
    std::vector<uint8_t> texels(size_t(size) * size * 4);
    auto unorm = [](double c) { return uint8_t(std::lround(255.0 * (c + 1.0) * 0.5)); };
    for (int v = 0; v < size; ++v)
        for (int u = 0; u < size; ++u) {
            const Vec3 d = decodeDouble(map, u, v);
            uint8_t* texel = &texels[4 * (size_t(v) * size + size_t(u))];
            texel[0] = unorm(d.x), texel[1] = unorm(d.y), texel[2] = unorm(d.z), texel[3] = 255;
        }
    return texels;
}

} // namespace ridge::lod
