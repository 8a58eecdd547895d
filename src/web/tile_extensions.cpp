#include "ridge/web/tile_extensions.h"

#include "ridge/core/error.h"
#include "ridge/lod/ellipsoid.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace ridge::web {

namespace {

constexpr std::pair<std::string_view, unsigned> kNames[] = {
    {"octvertexnormals", kOctVertexNormals},
    {"watermask", kWaterMask},
    {"metadata", kMetadata},
};

double signNotZero(double v)
{
    return v < 0.0 ? -1.0 : 1.0;
}

// Cesium's CesiumMath.toSNorm with rangeMax 255.
uint8_t toSnorm(double v)
{
    return uint8_t(std::lround((std::clamp(v, -1.0, 1.0) * 0.5 + 0.5) * 255.0));
}

// The grid line nearest `coordinate` among `lines` (sorted either way).
size_t nearestLine(const std::vector<int32_t>& lines, double coordinate)
{
    size_t best = 0;
    double best_distance = INFINITY;
    // Lines are few (at most a few hundred); the mask asks 256 times a side.
    for (size_t i = 0; i < lines.size(); ++i) {
        const double d = std::abs(double(lines[i]) - coordinate);
        if (d < best_distance) {
            best_distance = d;
            best = i;
        }
    }
    return best;
}

} // namespace

unsigned parseAcceptedExtensions(std::string_view accept)
{
    unsigned out = 0;
    constexpr std::string_view kKey = "extensions=";
    for (size_t at = accept.find(kKey); at != std::string_view::npos;
         at = accept.find(kKey, at + 1)) {
        size_t end = at + kKey.size();
        while (end < accept.size() && accept[end] != ';' && accept[end] != ',' &&
               accept[end] != ' ')
            ++end;
        std::string_view list = accept.substr(at + kKey.size(), end - at - kKey.size());
        while (!list.empty()) {
            const size_t dash = list.find('-');
            const std::string_view name = list.substr(0, dash);
            for (const auto& [known, bit] : kNames)
                if (name == known)
                    out |= bit;
            list = dash == std::string_view::npos ? std::string_view() : list.substr(dash + 1);
        }
    }
    return out;
}

std::string extensionNames(unsigned extensions)
{
    std::string out;
    for (const auto& [name, bit] : kNames)
        if (extensions & bit) {
            if (!out.empty())
                out += '-';
            out += name;
        }
    return out;
}

std::array<uint8_t, 2> octEncode(std::array<double, 3> n)
{
    const double sum = std::abs(n[0]) + std::abs(n[1]) + std::abs(n[2]);
    double x = n[0] / sum, y = n[1] / sum;
    if (n[2] < 0.0) {
        const double old_x = x;
        x = (1.0 - std::abs(y)) * signNotZero(old_x);
        y = (1.0 - std::abs(old_x)) * signNotZero(y);
    }
    return {toSnorm(x), toSnorm(y)};
}

std::array<double, 3> octDecode(uint8_t ex, uint8_t ey)
{
    double x = ex / 255.0 * 2.0 - 1.0, y = ey / 255.0 * 2.0 - 1.0;
    const double z = 1.0 - (std::abs(x) + std::abs(y));
    if (z < 0.0) {
        const double old_x = x;
        x = (1.0 - std::abs(y)) * signNotZero(old_x);
        y = (1.0 - std::abs(old_x)) * signNotZero(y);
    }
    const double length = std::sqrt(x * x + y * y + z * z);
    return {x / length, y / length, z / length};
}

std::vector<uint8_t> octVertexNormals(const QuantizedMesh& mesh, TileKey key)
{
    const size_t n = mesh.vertexCount();
    const GeoRect r = GeographicTms::rect(key);
    const lod::Ellipsoid wgs84 = lod::Ellipsoid::wgs84();
    constexpr double kRadians = std::numbers::pi / 180.0;
    constexpr double kMax = QuantizedMesh::kMaxCoordinate;
    std::vector<glm::dvec3> position(n), up(n), sum(n, glm::dvec3(0.0));
    for (uint32_t i = 0; i < n; ++i) {
        const double lon = (r.west + (r.east - r.west) * mesh.u[i] / kMax) * kRadians;
        const double lat = (r.south + (r.north - r.south) * mesh.v[i] / kMax) * kRadians;
        position[i] = lod::geodeticToEcef(wgs84, lon, lat, decodedHeight(mesh, i));
        up[i] = {std::cos(lat) * std::cos(lon), std::cos(lat) * std::sin(lon), std::sin(lat)};
    }
    for (size_t t = 0; t + 2 < mesh.triangles.size(); t += 3) {
        const uint32_t a = mesh.triangles[t], b = mesh.triangles[t + 1], c = mesh.triangles[t + 2];
        // Counter-clockwise seen from above: the cross product points up, its length twice
        // the area (so larger triangles weigh more).
        const glm::dvec3 face = glm::cross(position[b] - position[a], position[c] - position[a]);
        sum[a] += face;
        sum[b] += face;
        sum[c] += face;
    }
    std::vector<uint8_t> out(2 * n);
    for (size_t i = 0; i < n; ++i) {
        // A vertex of no triangle (or of degenerate ones only) gets the ellipsoid's normal.
        glm::dvec3 normal = glm::length(sum[i]) > 0.0 ? sum[i] : up[i];
        normal = glm::normalize(normal);
        const auto e = octEncode({normal.x, normal.y, normal.z});
        out[2 * i] = e[0];
        out[2 * i + 1] = e[1];
    }
    return out;
}

std::vector<uint8_t> waterMask(const TileHeights& grid, std::span<const uint8_t> water)
{
    if (water.size() != grid.u.size() * grid.v.size())
        throw Error("water mask of " + std::to_string(water.size()) + " flags for a grid of " +
                    std::to_string(grid.u.size()) + " × " + std::to_string(grid.v.size()));
    const bool any = std::any_of(water.begin(), water.end(), [](uint8_t w) { return w != 0; });
    const bool all = std::all_of(water.begin(), water.end(), [](uint8_t w) { return w != 0; });
    if (!any || all)
        return {uint8_t(all ? 255 : 0)};
    constexpr int kSide = 256;
    constexpr double kMax = QuantizedMesh::kMaxCoordinate;
    std::array<size_t, kSide> column{}, row{};
    for (int i = 0; i < kSide; ++i) {
        // Texel centres: u east from the west edge, v north from the south edge (row 0 north).
        column[size_t(i)] = nearestLine(grid.u, (i + 0.5) / kSide * kMax);
        row[size_t(i)] = nearestLine(grid.v, (kSide - i - 0.5) / kSide * kMax);
    }
    std::vector<uint8_t> out(size_t(kSide) * kSide);
    for (int j = 0; j < kSide; ++j)
        for (int i = 0; i < kSide; ++i)
            out[size_t(j) * kSide + size_t(i)] =
                water[row[size_t(j)] * grid.u.size() + column[size_t(i)]] ? 255 : 0;
    return out;
}

std::string availabilityMetadata(std::span<const TileRange> children)
{
    nlohmann::json ranges = nlohmann::json::array();
    for (const TileRange& r : children)
        if (!r.empty())
            ranges.push_back({{"startX", r.x0}, {"startY", r.y0}, {"endX", r.x1}, {"endY", r.y1}});
    if (ranges.empty())
        return "{}";
    return nlohmann::json{{"available", nlohmann::json::array({ranges})}}.dump();
}

} // namespace ridge::web
