#include "ridge/web/tile_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace ridge::web {

namespace {

constexpr double kWgs84A = 6378137.0; // semi-major axis, metres

bool inRange(TileKey k, int64_t nx, int64_t ny)
{
    return k.x >= 0 && k.x < nx && k.y >= 0 && k.y < ny;
}

// Latitude, degrees, of Mercator y measured in tiles from the north edge of the world.
double mercatorLatitude(double y_tiles, int z)
{
    const double n = std::numbers::pi * (1.0 - 2.0 * y_tiles / double(int64_t(1) << z));
    return std::atan(std::sinh(n)) * 180.0 / std::numbers::pi;
}

} // namespace

bool GeographicTms::valid(TileKey k)
{
    return k.z >= 0 && k.z <= kMaxTileZoom && inRange(k, tilesX(k.z), tilesY(k.z));
}

GeoRect GeographicTms::rect(TileKey k)
{
    return {longitude(k, 0, 1), latitude(k, 0, 1), longitude(k, 1, 1), latitude(k, 1, 1)};
}

TileKey GeographicTms::tileAt(int z, double lon, double lat)
{
    const double size = 180.0 / double(tilesY(z));
    const auto index = [&](double degrees, int64_t n) {
        return std::clamp(int64_t(std::floor(degrees / size)), int64_t(0), n - 1);
    };
    return {z, index(lon + 180.0, tilesX(z)), index(lat + 90.0, tilesY(z))};
}

// Global sample index over the zoom's samples, so a shared edge is one computation.
double GeographicTms::longitude(TileKey k, int64_t i, int cells)
{
    const double samples = double(tilesX(k.z)) * cells;
    return -180.0 + 360.0 * (double(k.x * cells + i) / samples);
}

double GeographicTms::latitude(TileKey k, int64_t j, int cells)
{
    const double samples = double(tilesY(k.z)) * cells;
    return -90.0 + 180.0 * (double(k.y * cells + j) / samples);
}

double GeographicTms::geometricError(int z)
{
    return kWgs84A * 2.0 * std::numbers::pi * 0.25 / (65.0 * 2.0) / std::ldexp(1.0, z);
}

bool WebMercatorXyz::valid(TileKey k)
{
    return k.z >= 0 && k.z <= kMaxTileZoom && inRange(k, tiles(k.z), tiles(k.z));
}

GeoRect WebMercatorXyz::rect(TileKey k)
{
    const double n = double(tiles(k.z));
    return {-180.0 + 360.0 * double(k.x) / n, mercatorLatitude(double(k.y + 1), k.z),
            -180.0 + 360.0 * double(k.x + 1) / n, mercatorLatitude(double(k.y), k.z)};
}

double WebMercatorXyz::longitude(TileKey k, double i, int size)
{
    return -180.0 + 360.0 * (double(k.x) + (i + 0.5) / size) / double(tiles(k.z));
}

double WebMercatorXyz::latitude(TileKey k, double j, int size)
{
    return mercatorLatitude(double(k.y) + (j + 0.5) / size, k.z);
}

double WebMercatorXyz::metresPerPixel(int z, double lat, int size)
{
    return 2.0 * std::numbers::pi * kWgs84A * std::cos(lat * std::numbers::pi / 180.0) /
           (double(tiles(z)) * size);
}

GeoRect clientBounds(const GeoRect& e)
{
    constexpr double kMercatorLimit = 85.0511287798;
    const bool world = e.east - e.west >= 360.0 || e.east > 180.0 || e.west < -180.0;
    return {world ? -180.0 : e.west, std::max(e.south, -kMercatorLimit), world ? 180.0 : e.east,
            std::min(e.north, kMercatorLimit)};
}

namespace {

// A decimal without sign or leading zeros, at most 18 digits; advances `s` past it.
std::optional<int64_t> parseIndex(std::string_view& s)
{
    size_t n = 0;
    while (n < s.size() && s[n] >= '0' && s[n] <= '9')
        ++n;
    if (n == 0 || n > 18 || (n > 1 && s[0] == '0'))
        return std::nullopt;
    int64_t v = 0;
    for (size_t i = 0; i < n; ++i)
        v = v * 10 + (s[i] - '0');
    s.remove_prefix(n);
    return v;
}

} // namespace

std::optional<TileKey> parseTilePath(std::string_view path, std::string_view extension)
{
    if (!path.ends_with(extension))
        return std::nullopt;
    path.remove_suffix(extension.size());
    TileKey k;
    for (int part = 0; part < 3; ++part) {
        if (part > 0) {
            if (path.empty() || path[0] != '/')
                return std::nullopt;
            path.remove_prefix(1);
        }
        const std::optional<int64_t> v = parseIndex(path);
        if (!v)
            return std::nullopt;
        if (part == 0 && *v > std::numeric_limits<int>::max())
            return std::nullopt;
        if (part == 0)
            k.z = int(*v);
        else if (part == 1)
            k.x = *v;
        else
            k.y = *v;
    }
    if (!path.empty())
        return std::nullopt;
    return k;
}

} // namespace ridge::web
