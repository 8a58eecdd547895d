#pragma once
// The tilings web clients ask for terrain in (plain C++, no I/O).
//
// GeographicTms: Cesium's geographic tiling scheme in TMS order, the tiling of
// quantized-mesh-1.0 (layer.json "projection": "EPSG:4326", "scheme": "tms"): at zoom z,
// 2^(z+1) × 2^z tiles of 180/2^z degrees, x from −180° eastwards, y from −90° northwards.
// WebMercatorXyz: the XYZ tiling of terrain-RGB (EPSG:3857, y from the north), 2^z × 2^z tiles
// at zoom z, latitudes within ±85.0511°.
//
// Sample positions are computed from global integer indices (the tile's first sample plus j,
// over the zoom's samples), never from a tile's own corner plus an offset: two tiles of a
// zoom that share an edge compute bit-identical coordinates for its samples, so the heights
// read there are identical and the meshes' shared edges carry identical vertices.
#include <cstdint>
#include <optional>
#include <string_view>

namespace ridge::web {

struct TileKey {
    int z = 0;
    int64_t x = 0, y = 0;
    friend bool operator==(const TileKey&, const TileKey&) = default;
};

// Degrees: longitude west..east, latitude south..north.
struct GeoRect {
    double west = 0, south = 0, east = 0, north = 0;
};

// The deepest zoom either tiling answers: 2^29 tiles across (7.5 cm at the equator on
// geographic tiles of 65 samples), far past any archive's finest spacing.
constexpr int kMaxTileZoom = 28;

class GeographicTms {
  public:
    static int64_t tilesX(int z) { return int64_t(2) << z; }
    static int64_t tilesY(int z) { return int64_t(1) << z; }
    // z in [0, kMaxTileZoom], x and y within the zoom's tiles.
    static bool valid(TileKey k);
    // The tile's extent; `k` must be valid.
    static GeoRect rect(TileKey k);
    // The tile of zoom z holding (lon, lat) degrees (on a shared edge, the east or north
    // one; clamped into the zoom's tiles).
    static TileKey tileAt(int z, double lon, double lat);
    // Longitude and latitude of sample (i, j) of a tile sampled with `cells` cells a side
    // (i east from its west edge, j north from its south edge, 0..cells).
    static double longitude(TileKey k, int64_t i, int cells);
    static double latitude(TileKey k, int64_t j, int cells);
    // The geometric error, metres, Cesium assumes for a tile of zoom z of this tiling
    // (EllipsoidTerrainProvider's estimate for a 65-sample heightmap over 2 root tiles on
    // WGS 84: 2π·a/4 / (65·2) / 2^z, 77,067 m at zoom 0): a tile whose mesh lies within it of
    // the terrain is refined exactly when the client expects.
    static double geometricError(int z);
};

class WebMercatorXyz {
  public:
    static int64_t tiles(int z) { return int64_t(1) << z; }
    static bool valid(TileKey k);
    // The tile's extent in degrees (latitudes from the Mercator y); `k` must be valid.
    static GeoRect rect(TileKey k);
    // Longitude and latitude of pixel centre (i, j) of a tile of `size` pixels a side (i east,
    // j south from the north edge).
    static double longitude(TileKey k, double i, int size);
    static double latitude(TileKey k, double j, int size);
    // Ground metres per pixel at latitude `lat` (degrees) for tiles of `size` pixels at zoom z.
    static double metresPerPixel(int z, double lat, int size);
};

// An extent as clients take bounds (TileJSON, PMTiles headers, Web Mercator tile ranges):
// one box within ±180°, which cannot cross the antimeridian, so an extent past 180° E (a
// 0..360° grid) or 360° wide is the whole world; latitudes within Web Mercator's ±85.0511°.
GeoRect clientBounds(const GeoRect& extent);

// "z/x/y" with an optional ".ext" suffix equal to `extension` (e.g. ".terrain"): the key, or
// nullopt for anything else (signs, spaces, leading zeros beyond "0", more than 18 digits, a
// zoom past INT_MAX, other suffixes). A key that parses may still lie outside a tiling
// (valid() says): a server answers 400 for the one and 404 for the other.
std::optional<TileKey> parseTilePath(std::string_view path, std::string_view extension);

} // namespace ridge::web
