#pragma once
// One archive served as a quantized-mesh tileset (GL-free, HTTP-free, thread-safe): what
// `ridge serve` answers for /NAME/layer.json and /NAME/{z}/{x}/{y}.terrain, and what
// `ridge tiles` writes.
//
// Tiles are made on request from the archive (no pre-pass) by a pool of TileSamplers, each
// with its own bounded decoded-patch cache: at most `samplers` tiles are made at once and
// memory is bounded by samplers × cache_patches decoded patches.
//
// Availability: zoom 0's two root tiles always (a root the archive misses is read like any
// other: the archive's edge fading out to 0 m, tile_sampler.h); below, the tiles that overlap
// the archive's longitude/latitude extent, down to TileSampler::maxZoom. Every other key is
// not available (nullopt: HTTP 404).
//
// A replaced archive (another file renamed over the path, or the file rewritten) is noticed
// on the next request and reopened; its tiles then carry a new version. While the new file
// cannot be opened (half written), the old one keeps being served from its open handle —
// where it was overwritten in place, reading it fails its checksums and the tile is refused
// (ridge::Error), never served corrupt.
#include "ridge/pipeline/height_query.h"
#include "ridge/web/terrain_rgb.h"
#include "ridge/web/tile_extensions.h"
#include "ridge/web/tile_grid.h"

#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace ridge::web {

class TileSampler;

// Where the watermask extension's water comes from.
enum class WaterSource {
    None,   // every tile land
    Nodata, // samples off the archive or on its kept nodata
    Water,  // those, and samples the archive flags as water (`ridge build --sea-level`)
};
const char* waterSourceName(WaterSource source); // "none", "nodata", "water"
std::optional<WaterSource> parseWaterSource(std::string_view name);

struct TilesetOptions {
    static constexpr int kMaxSamplers = 256;
    int cells = 64; // grid cells a side a tile is sampled with, [1, 4096]
    WaterSource water = WaterSource::Nodata;
    int samplers = 2; // tiles made at once, [1, kMaxSamplers]
    // Quantized-mesh heights above the WGS 84 ellipsoid, as Cesium places them: an archive
    // whose heights are above a registered vertical datum (EGM96 height, ...) is converted
    // through PROJ (TileSampler::toEllipsoid). Off: the archive's heights as stored.
    // Terrain-RGB always keeps the archive's heights (MapLibre draws heights above sea level).
    bool ellipsoidal = true;
    // The EPSG code of the archive's vertical datum when the archive names none (`ridge serve
    // --vertical-datum`); ignored when it names one or its heights are ellipsoidal.
    std::optional<int> vertical_datum;
    size_t cache_patches = HeightQuery::kDefaultCachePatches; // per sampler, >= 1
    // Throws ridge::Error naming the field out of range.
    void validate() const;
};

// A quantized-mesh tile, uncompressed, and what it claims.
struct ServedTile {
    std::vector<uint8_t> bytes;
    double claimed_error = 0.0; // metres: every finest sample within it (client_tile.h)
    bool flat = false;          // a tile none of whose points PROJ could place (0 m, the ellipsoid)
    std::string version;        // the archive's version it was made from
};

class Tileset {
  public:
    // Opens `path` (throws ridge::Error as TileSampler does, or for invalid options). `name`
    // is the tileset's URL segment.
    Tileset(std::string name, std::string path, const TilesetOptions& options);
    ~Tileset();
    Tileset(const Tileset&) = delete;
    Tileset& operator=(const Tileset&) = delete;

    const std::string& name() const { return name_; }
    const std::string& path() const { return path_; }
    const TilesetOptions& options() const { return options_; }

    struct Info {
        GeoRect extent;              // the archive's lon/lat box (TileSampler::extent)
        int max_zoom = 0;            // the deepest zoom served
        std::string heights;         // of quantized-mesh tiles: "ellipsoid", a datum, "unknown"
        std::string archive_heights; // TileSampler::verticalReference (terrain-RGB's)
        std::string conversion;      // how heights became ellipsoidal, when they did
        std::string version;         // 16 hex digits, changes when the archive is replaced
        double max_bound = 0;        // the archive's largest Err(P), metres
    };
    // The archive served now (reopened first if it was replaced).
    Info info();

    // The tiles of zoom z that are available (one range, or two across the antimeridian;
    // none past max_zoom).
    std::vector<TileRange> available(int z);
    // TileJSON-style layer.json for Cesium's CesiumTerrainProvider: tiles, scheme "tms",
    // projection EPSG:4326, available, extensions, and ridge's statement of what the heights
    // are above and what error each zoom's tiles keep. With `versioned`, the tiles template
    // carries "?v=VERSION" so a replaced archive's tiles get new URLs.
    std::string layerJson(bool versioned);

    // The tile `k` with `extensions` (TileExtension bits), or nullopt when not available.
    // Throws ridge::Error when the archive cannot be read (a corrupt or vanished patch).
    std::optional<ServedTile> terrain(TileKey k, unsigned extensions);

    // Terrain-RGB (terrain_rgb.h) in Web Mercator XYZ: tiles of `size` pixels (256 or 512)
    // down to TileSampler::maxMercatorZoom that overlap the archive; nullopt elsewhere.
    // Throws as terrain() does.
    std::optional<RgbTile> terrainRgb(TileKey k, int size, RgbEncoding encoding,
                                      ImageFormat format);
    int rgbMaxZoom(int size);
    // TileJSON 3.0.0 for a MapLibre raster-dem source: the tile template relative to the
    // TileJSON's URL ("mapbox/{z}/{x}/{y}.png?v=VERSION", "@2x" for 512 px; with `served`
    // false, for files beside it: "{z}/{x}/{y}.png"), tileSize, encoding, zooms, bounds, and
    // ridge's statement of the vertical step rule.
    std::string rgbTileJson(RgbEncoding encoding, int size, ImageFormat format, bool served = true);

  private:
    struct State;
    std::shared_ptr<State> current();
    std::vector<TileRange> availableIn(const State& state, int z) const;
    ServedTile make(State& state, TileSampler& sampler, TileKey k, unsigned extensions);

    std::string name_, path_;
    TilesetOptions options_;
    std::mutex mutex_; // guards state_ and the replacement check
    std::shared_ptr<State> state_;
    std::chrono::steady_clock::time_point next_retry_{};
};

} // namespace ridge::web
