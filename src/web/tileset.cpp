#include "ridge/web/tileset.h"

#include "ridge/core/error.h"
#include "ridge/core/file_io.h"
#include "ridge/web/client_tile.h"
#include "ridge/web/tile_sampler.h"

#include <nlohmann/json.hpp>
#include <sys/stat.h>

#include <algorithm>
#include <cinttypes>
#include <cmath>
#include <cstdio>

namespace ridge::web {

namespace {

// How often a failed reopen of a replaced archive is retried.
constexpr std::chrono::milliseconds kRetryAfter{1000};

// What tells one file at the path from another: a renamed-over file has another inode, one
// rewritten in place another size or modification time.
struct FileIdentity {
    uint64_t device = 0, inode = 0, size = 0;
    int64_t mtime_ns = 0;
    friend bool operator==(const FileIdentity&, const FileIdentity&) = default;
};

std::optional<FileIdentity> identityOf(const std::string& path)
{
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0)
        return std::nullopt;
    return FileIdentity{uint64_t(st.st_dev), uint64_t(st.st_ino), uint64_t(st.st_size),
                        int64_t(st.st_mtim.tv_sec) * 1000000000 + st.st_mtim.tv_nsec};
}

// A hash of the identity (a version string, not a security token).
std::string versionOf(const FileIdentity& id)
{
    const uint64_t words[4] = {id.device, id.inode, id.size, uint64_t(id.mtime_ns)};
    char text[17];
    std::snprintf(text, sizeof text, "%016" PRIx64, fnv1a64(words, sizeof words));
    return text;
}

// Tile indices [first, last] of zoom z's `count` tiles of `size` degrees that overlap
// [lo, hi] degrees measured from the tiling's origin.
std::pair<int64_t, int64_t> indexRange(double lo, double hi, double size, int64_t count)
{
    const int64_t first = std::clamp(int64_t(std::floor(lo / size)), int64_t(0), count - 1);
    const int64_t last = std::clamp(int64_t(std::ceil(hi / size)) - 1, first, count - 1);
    return {first, last};
}

} // namespace

const char* waterSourceName(WaterSource source)
{
    switch (source) {
    case WaterSource::None:
        return "none";
    case WaterSource::Nodata:
        return "nodata";
    case WaterSource::Water:
        return "water";
    }
    return "?";
}

std::optional<WaterSource> parseWaterSource(std::string_view name)
{
    for (const WaterSource s : {WaterSource::None, WaterSource::Nodata, WaterSource::Water})
        if (name == waterSourceName(s))
            return s;
    return std::nullopt;
}

void TilesetOptions::validate() const
{
    if (cells < 1 || cells > 4096)
        throw Error("tile cells " + std::to_string(cells) + " outside [1, 4096]");
    if (samplers < 1 || samplers > kMaxSamplers)
        throw Error("tile samplers " + std::to_string(samplers) + " outside [1, " +
                    std::to_string(kMaxSamplers) + "]");
    if (cache_patches < 1)
        throw Error("tile cache_patches must be at least 1");
}

// The archive as opened once: its samplers (a pool) and what every request reads.
struct Tileset::State {
    FileIdentity identity;
    Info info;
    std::vector<std::unique_ptr<TileSampler>> samplers;
    std::mutex mutex; // guards idle
    std::condition_variable released;
    std::vector<TileSampler*> idle;

    // A sampler for the caller alone until the lease ends.
    class Lease {
      public:
        explicit Lease(State& s) : s_(s)
        {
            std::unique_lock lock(s_.mutex);
            s_.released.wait(lock, [&] { return !s_.idle.empty(); });
            sampler_ = s_.idle.back();
            s_.idle.pop_back();
        }
        ~Lease()
        {
            {
                std::lock_guard lock(s_.mutex);
                s_.idle.push_back(sampler_);
            }
            s_.released.notify_one();
        }
        Lease(const Lease&) = delete;
        Lease& operator=(const Lease&) = delete;
        TileSampler& operator*() const { return *sampler_; }

      private:
        State& s_;
        TileSampler* sampler_ = nullptr;
    };

    State(const std::string& path, const FileIdentity& id, const TilesetOptions& options)
        : identity(id)
    {
        for (int i = 0; i < options.samplers; ++i) {
            samplers.push_back(std::make_unique<TileSampler>(path, options.cache_patches));
            idle.push_back(samplers.back().get());
        }
        TileSampler& first = *samplers.front();
        info.extent = first.extent();
        info.max_zoom = first.maxZoom(options.cells);
        info.archive_heights = first.verticalReference();
        info.heights = info.archive_heights;
        // Geoid heights onto the ellipsoid for Cesium, where the datum is known.
        std::optional<int> epsg = first.verticalDatumEpsg();
        std::string datum = info.archive_heights;
        if (!epsg && info.archive_heights == "unknown" && options.vertical_datum) {
            epsg = options.vertical_datum;
            datum = "EPSG:" + std::to_string(*epsg) + " (as told)";
        }
        if (options.ellipsoidal && epsg) {
            std::string operation;
            for (const auto& s : samplers)
                operation = s->toEllipsoid(*epsg, datum);
            info.heights = "ellipsoid";
            info.conversion = datum + " + N through PROJ (" + operation + ")";
        }
        info.version = versionOf(id);
        const archive::ArchiveReader& reader = first.reader();
        for (int level = 0; level <= reader.geometry().finestLevel(); ++level)
            info.max_bound = std::max(info.max_bound, reader.levelErrorBound(level));
    }
};

Tileset::Tileset(std::string name, std::string path, const TilesetOptions& options)
    : name_(std::move(name)), path_(std::move(path)), options_(options)
{
    options_.validate();
    const std::optional<FileIdentity> id = identityOf(path_);
    if (!id)
        throw Error(path_ + ": cannot be read");
    state_ = std::make_shared<State>(path_, *id, options_);
}

Tileset::~Tileset() = default;

std::shared_ptr<Tileset::State> Tileset::current()
{
    std::lock_guard lock(mutex_);
    const std::optional<FileIdentity> id = identityOf(path_);
    if (id && !(*id == state_->identity) && std::chrono::steady_clock::now() >= next_retry_) {
        try {
            state_ = std::make_shared<State>(path_, *id, options_);
        } catch (const std::exception& e) {
            // Half written, or not an archive (yet): keep serving the one open.
            next_retry_ = std::chrono::steady_clock::now() + kRetryAfter;
            std::fprintf(stderr,
                         "ridge serve: %s was replaced and cannot be opened yet (%s); "
                         "serving the archive opened before\n",
                         path_.c_str(), e.what());
        }
    }
    return state_;
}

Tileset::Info Tileset::info()
{
    return current()->info;
}

std::vector<TileRange> Tileset::available(int z)
{
    return availableIn(*current(), z);
}

std::vector<TileRange> Tileset::availableIn(const State& state, int z) const
{
    if (z < 0 || z > state.info.max_zoom)
        return {};
    const int64_t nx = GeographicTms::tilesX(z), ny = GeographicTms::tilesY(z);
    if (z == 0)
        return {TileRange{0, 0, nx - 1, ny - 1}};
    const double size = 180.0 / double(ny);
    const GeoRect& e = state.info.extent;
    const auto [y0, y1] = indexRange(e.south + 90.0, e.north + 90.0, size, ny);
    double west = e.west, east = e.east;
    if (east - west >= 360.0)
        return {TileRange{0, y0, nx - 1, y1}};
    while (west >= 180.0) {
        west -= 360.0;
        east -= 360.0;
    }
    while (west < -180.0) {
        west += 360.0;
        east += 360.0;
    }
    std::vector<TileRange> out;
    const auto [x0, x1] = indexRange(west + 180.0, std::min(east, 180.0) + 180.0, size, nx);
    out.push_back({x0, y0, x1, y1});
    if (east > 180.0) { // across the antimeridian: the part past it from x = 0
        const auto [w0, w1] = indexRange(0.0, east - 180.0, size, nx);
        if (w0 > x1 || w1 < x0)
            out.push_back({w0, y0, std::min(w1, x0 - 1), y1});
    }
    return out;
}

std::string Tileset::layerJson(bool versioned)
{
    const std::shared_ptr<State> state = current();
    const Info& info = state->info;
    nlohmann::json available = nlohmann::json::array();
    for (int z = 0; z <= info.max_zoom; ++z) {
        nlohmann::json level = nlohmann::json::array();
        for (const TileRange& r : availableIn(*state, z))
            level.push_back({{"startX", r.x0}, {"startY", r.y0}, {"endX", r.x1}, {"endY", r.y1}});
        available.push_back(std::move(level));
    }
    const std::string tiles =
        std::string("{z}/{x}/{y}.terrain") + (versioned ? "?v={version}" : "");
    nlohmann::json layer = {
        {"tilejson", "2.1.0"},
        {"name", name_},
        {"description", "ridge quantized-mesh tiles of " + name_},
        {"version", info.version},
        {"format", "quantized-mesh-1.0"},
        {"scheme", "tms"},
        {"projection", "EPSG:4326"},
        {"tiles", {tiles}},
        {"minzoom", 0},
        {"maxzoom", info.max_zoom},
        {"bounds", {info.extent.west, info.extent.south, info.extent.east, info.extent.north}},
        {"available", available},
        {"extensions", {"octvertexnormals", "watermask", "metadata"}},
        // Each tile's metadata names its children (one level): CesiumJS reads tile
        // availability from there only when this says how many levels a tile covers.
        {"metadataAvailability", 1},
        {"attribution", ""},
        // What Cesium does not ask but a user of the tiles must know.
        {"ridge",
         {{"heights", info.heights == "ellipsoid"
                          ? "above the WGS 84 ellipsoid" +
                                (info.conversion.empty() ? std::string()
                                                         : ", converted from " + info.conversion)
                          : "above " + info.heights +
                                " (not converted: Cesium expects ellipsoidal heights; name the "
                                "datum with --vertical-datum to convert)"},
          {"verticalReference", info.heights},
          {"tileError",
           "each tile's mesh lies within max(TIN bound + half height step, measured) + the "
           "archive's Err(P) of every finest sample, kept within the client's geometric "
           "error 2*pi*6378137/4/(65*2)/2^z m where the archive's bound allows"},
          {"archiveMaxError", info.max_bound},
          {"cells", options_.cells},
          {"watermask", waterSourceName(options_.water)}}},
    };
    return layer.dump(1);
}

std::optional<ServedTile> Tileset::terrain(TileKey k, unsigned extensions)
{
    const std::shared_ptr<State> state = current();
    if (!GeographicTms::valid(k) || k.z > state->info.max_zoom)
        return std::nullopt;
    const std::vector<TileRange> ranges = availableIn(*state, k.z);
    if (std::none_of(ranges.begin(), ranges.end(),
                     [&](const TileRange& r) { return r.contains(k.x, k.y); }))
        return std::nullopt;
    State::Lease sampler(*state);
    return make(*state, *sampler, k, extensions);
}

std::optional<RgbTile> Tileset::terrainRgb(TileKey k, int size, RgbEncoding encoding,
                                           ImageFormat format)
{
    const std::shared_ptr<State> state = current();
    if (!WebMercatorXyz::valid(k) || (size != 256 && size != 512) ||
        k.z > state->samplers.front()->maxMercatorZoom(size) ||
        !state->samplers.front()->overlapsMercator(k))
        return std::nullopt;
    State::Lease sampler(*state);
    return makeRgbTile(*sampler, k, size, encoding, format);
}

int Tileset::rgbMaxZoom(int size)
{
    return current()->samplers.front()->maxMercatorZoom(size);
}

std::string Tileset::rgbTileJson(RgbEncoding encoding, int size, ImageFormat format, bool served)
{
    const std::shared_ptr<State> state = current();
    const Info& info = state->info;
    const std::string name = std::string(rgbEncodingName(encoding)) + (size == 512 ? "@2x" : "");
    const GeoRect bounds = clientBounds(info.extent);
    const nlohmann::json json = {
        {"tilejson", "3.0.0"},
        {"name", name_ + " " + name},
        {"version", info.version},
        {"scheme", "xyz"},
        {"tiles",
         {served ? name + "/{z}/{x}/{y}." + imageFormatName(format) + "?v=" + info.version
                 : std::string("{z}/{x}/{y}.") + imageFormatName(format)}},
        {"tileSize", size},
        {"encoding", rgbEncodingName(encoding)},
        {"minzoom", 0},
        {"maxzoom", state->samplers.front()->maxMercatorZoom(size)},
        {"bounds", {bounds.west, bounds.south, bounds.east, bounds.north}},
        {"ridge",
         {{"heights", "above " + info.archive_heights + ", as the archive stores them"},
          {"nativeStep", nativeStep(encoding)},
          {"step", "native step x 2^k, the largest within pixel size / 1000 and the archive's "
                   "Err(P) over the tile (header X-Ridge-Step gives each tile's)"},
          {"error", "each pixel within step/2 of the archive level's surface at its centre, "
                    "within step/2 + Err(P) (header X-Ridge-Archive-Error) of the finest "
                    "samples"}}},
    };
    return json.dump(1);
}

ServedTile Tileset::make(State& state, TileSampler& sampler, TileKey k, unsigned extensions)
{
    ServedTile out;
    out.version = state.info.version;
    // Every available tile is read, the ones the archive misses too (its edge fading out to
    // 0 m: tile_sampler.h), so that a root tile meets its neighbour.
    std::optional<ClientTile> tile = makeClientTile(sampler, k, options_.cells);
    std::vector<uint8_t> water;
    TerrainTile flat;
    if (!tile) {
        // Available but nothing could be read (PROJ placed none of its points): the
        // ellipsoid.
        // A 16-cell grid, so that the mesh can follow the globe within the client's error.
        TileHeights grid = uniformTileHeights(k, 16);
        grid.heights.assign(17 * 17, 0.f);
        flat = makeTerrainTile(grid, GeographicTms::geometricError(k.z));
        out.flat = true;
        out.claimed_error = flat.error;
        water.assign(17 * 17, options_.water == WaterSource::None ? 0 : 1);
        tile.emplace();
        tile->tile = std::move(flat);
        tile->grid = std::move(grid);
    } else {
        out.claimed_error = tile->claimed_error;
        water.resize(tile->flags.size());
        for (size_t i = 0; i < water.size(); ++i) {
            const uint8_t f = tile->flags[i];
            water[i] = (options_.water != WaterSource::None && (f & SampledTile::kAbsent)) ||
                       (options_.water == WaterSource::Water && (f & SampledTile::kWater));
        }
    }
    QuantizedMesh& mesh = tile->tile.mesh;
    if (extensions & kOctVertexNormals)
        mesh.oct_normals = octVertexNormals(mesh, k);
    if (extensions & kWaterMask)
        mesh.water_mask = waterMask(tile->grid, water);
    if (extensions & kMetadata) {
        // The children that are available: this tile's four, cut by zoom z+1's ranges.
        const TileRange children{2 * k.x, 2 * k.y, 2 * k.x + 1, 2 * k.y + 1};
        std::vector<TileRange> present;
        for (const TileRange& r : availableIn(state, k.z + 1))
            present.push_back({std::max(r.x0, children.x0), std::max(r.y0, children.y0),
                               std::min(r.x1, children.x1), std::min(r.y1, children.y1)});
        mesh.metadata = availabilityMetadata(present);
    }
    out.bytes = encodeQuantizedMesh(mesh);
    return out;
}

} // namespace ridge::web
