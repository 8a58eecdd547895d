#include "ridge/web/tile_writer.h"

#include "ridge/core/atomic_output.h"
#include "ridge/core/error.h"
#include "ridge/core/file_identity.h"
#include "ridge/core/file_io.h"
#include "ridge/web/gzip.h"
#include "ridge/web/pmtiles.h"

#include <fcntl.h>
#include <nlohmann/json.hpp>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstring>
#include <filesystem>
#include <map>
#include <mutex>
#include <numbers>
#include <thread>

namespace ridge::web {

namespace {

namespace fs = std::filesystem;

bool isPmtiles(const std::string& path)
{
    return path.size() > 8 && path.substr(path.size() - 8) == ".pmtiles";
}

std::string keyPath(TileKey k, const char* extension)
{
    return std::to_string(k.z) + "/" + std::to_string(k.x) + "/" + std::to_string(k.y) + "." +
           extension;
}

// Web Mercator tile row of latitude `lat` at zoom z (clamped into the zoom).
int64_t mercatorRow(double lat, int z)
{
    const double clamped = lat * std::numbers::pi / 180; // within ±85.05° (clientBounds)
    const double n = double(int64_t(1) << z);
    const double y =
        (1.0 - std::log(std::tan(clamped) + 1.0 / std::cos(clamped)) / std::numbers::pi) / 2.0 * n;
    return std::clamp(int64_t(std::floor(y)), int64_t(0), int64_t(n) - 1);
}

// The tiles to write, in the order they are stored (PMTiles: tile id; a directory: the same).
std::vector<TileKey> tileList(Tileset& set, const TileWriteOptions& o, int max_zoom)
{
    std::vector<TileKey> keys;
    if (o.format == TileFormat::QuantizedMesh) {
        for (int z = o.min_zoom; z <= max_zoom; ++z)
            for (const TileRange& r : set.available(z))
                for (int64_t y = r.y0; y <= r.y1; ++y)
                    for (int64_t x = r.x0; x <= r.x1; ++x)
                        keys.push_back({z, x, y});
    } else {
        const GeoRect e = clientBounds(set.info().extent);
        for (int z = o.min_zoom; z <= max_zoom; ++z) {
            const int64_t n = int64_t(1) << z;
            const auto column = [&](double lon) {
                return std::clamp(int64_t(std::floor((lon + 180.0) / 360.0 * double(n))),
                                  int64_t(0), n - 1);
            };
            const int64_t x0 = column(e.west), x1 = column(e.east);
            for (int64_t y = mercatorRow(e.north, z); y <= mercatorRow(e.south, z); ++y)
                for (int64_t x = x0; x <= x1; ++x)
                    keys.push_back({z, x, y});
        }
    }
    return keys;
}

// PMTiles' key of a tile: geographic TMS tiles one zoom down (pmtiles.h).
TileKey storedKey(TileFormat format, TileKey k)
{
    return format == TileFormat::QuantizedMesh ? TileKey{k.z + 1, k.x, k.y} : k;
}

// A temporary sibling directory, removed unless released.
class TemporaryDirectory {
  public:
    explicit TemporaryDirectory(const fs::path& final_path)
    {
        const fs::path parent =
            final_path.parent_path().empty() ? fs::path(".") : final_path.parent_path();
        std::string name = ".";
        name += final_path.filename().string();
        name += ".ridge-tmp-XXXXXX";
        std::string pattern = (parent / name).string();
        if (!::mkdtemp(pattern.data()))
            throw Error(final_path.string() + ": cannot write: " + std::strerror(errno));
        path_ = pattern;
    }
    ~TemporaryDirectory()
    {
        if (!path_.empty()) {
            std::error_code ignored;
            fs::remove_all(path_, ignored);
        }
    }
    const fs::path& path() const { return path_; }
    void release() { path_.clear(); }

  private:
    fs::path path_;
};

void writeFile(const fs::path& path, std::span<const uint8_t> bytes)
{
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
    if (fd < 0)
        throw Error(path.string() + ": cannot write: " + std::strerror(errno));
    try {
        writeAll(fd, bytes.data(), bytes.size(), path.string());
    } catch (...) {
        ::close(fd);
        throw;
    }
    if (::close(fd) != 0)
        throw Error(path.string() + ": cannot write: " + std::strerror(errno));
}

// Makes tiles keys[i] on `threads` workers and hands them to `consume(i, bytes)` on the
// calling thread in order (nullopt: not available there), at most `window` tiles ahead.
template <class Make, class Consume>
void makeInOrder(const std::vector<TileKey>& keys, int threads, Make make, Consume consume,
                 const Progress& progress)
{
    const size_t window = size_t(threads) * 4;
    std::mutex mutex;
    std::condition_variable changed;
    std::map<size_t, std::optional<std::vector<uint8_t>>> made;
    size_t consumed = 0;
    std::atomic<size_t> next{0};
    bool stop = false;
    std::exception_ptr failure;
    std::vector<std::thread> workers;
    for (int t = 0; t < threads; ++t)
        workers.emplace_back([&] {
            while (true) {
                const size_t i = next++;
                if (i >= keys.size())
                    return;
                {
                    std::unique_lock lock(mutex);
                    changed.wait(lock, [&] { return stop || i < consumed + window; });
                    if (stop)
                        return;
                }
                try {
                    std::optional<std::vector<uint8_t>> tile = make(keys[i]);
                    std::lock_guard lock(mutex);
                    made.emplace(i, std::move(tile));
                } catch (...) {
                    std::lock_guard lock(mutex);
                    if (!failure)
                        failure = std::current_exception();
                    stop = true;
                }
                changed.notify_all();
            }
        });
    const auto finish = [&] {
        {
            std::lock_guard lock(mutex);
            stop = true;
        }
        changed.notify_all();
        for (std::thread& w : workers)
            w.join();
    };
    try {
        while (consumed < keys.size()) {
            std::optional<std::vector<uint8_t>> tile;
            {
                std::unique_lock lock(mutex);
                changed.wait(lock, [&] { return failure || made.count(consumed); });
                if (failure)
                    std::rethrow_exception(failure);
                tile = std::move(made[consumed]);
                made.erase(consumed);
            }
            consume(consumed, tile);
            {
                std::lock_guard lock(mutex);
                ++consumed;
            }
            changed.notify_all();
            reportProgress(progress, double(consumed) / double(keys.size()));
        }
    } catch (...) {
        finish();
        throw;
    }
    finish();
}

} // namespace

const char* tileFormatName(TileFormat format)
{
    switch (format) {
    case TileFormat::QuantizedMesh:
        return "quantized-mesh";
    case TileFormat::MapboxRgb:
        return "terrain-rgb";
    case TileFormat::TerrariumRgb:
        return "terrarium";
    }
    return "?";
}

std::optional<TileFormat> parseTileFormat(std::string_view name)
{
    for (const TileFormat f :
         {TileFormat::QuantizedMesh, TileFormat::MapboxRgb, TileFormat::TerrariumRgb})
        if (name == tileFormatName(f))
            return f;
    return std::nullopt;
}

void TileWriteOptions::validate() const
{
    if (size != 256 && size != 512)
        throw Error("tile size " + std::to_string(size) + ": must be 256 or 512");
    if (min_zoom < 0 || min_zoom > kMaxTileZoom)
        throw Error("min zoom " + std::to_string(min_zoom) + " outside [0, " +
                    std::to_string(kMaxTileZoom) + "]");
    if (max_zoom < -1 || max_zoom > kMaxTileZoom)
        throw Error("max zoom " + std::to_string(max_zoom) + " outside [0, " +
                    std::to_string(kMaxTileZoom) + "] (or -1: the archive's deepest)");
    if (max_zoom >= 0 && max_zoom < min_zoom)
        throw Error("max zoom " + std::to_string(max_zoom) + " below min zoom " +
                    std::to_string(min_zoom));
    if (threads < 0 || threads > TilesetOptions::kMaxSamplers)
        throw Error("tile threads " + std::to_string(threads) + " outside [0, " +
                    std::to_string(TilesetOptions::kMaxSamplers) + "]");
}

TileWriteReport writeTiles(const std::string& archive, const std::string& output,
                           const TileWriteOptions& options)
{
    options.validate();
    refuseOutputOverInput(output, {archive});
    const auto start = std::chrono::steady_clock::now();
    const bool pmtiles = isPmtiles(output);
    if (!pmtiles && fs::exists(fs::symlink_status(output)))
        throw Error(output + ": exists; ridge tiles writes a new directory (remove it first)");

    TileWriteReport report;
    report.threads = options.threads > 0
                         ? options.threads
                         : int(std::clamp(std::thread::hardware_concurrency(), 1u, 64u));
    TilesetOptions tileset_options = options.tileset;
    tileset_options.samplers = report.threads;
    Tileset set("tiles", archive, tileset_options);
    const bool mesh = options.format == TileFormat::QuantizedMesh;
    const RgbEncoding encoding =
        options.format == TileFormat::MapboxRgb ? RgbEncoding::Mapbox : RgbEncoding::Terrarium;
    const int deepest = mesh ? set.info().max_zoom : set.rgbMaxZoom(options.size);
    report.min_zoom = options.min_zoom;
    report.max_zoom = options.max_zoom < 0 ? deepest : options.max_zoom;
    if (report.max_zoom > deepest || report.min_zoom > report.max_zoom)
        throw Error(archive + ": --maxzoom " + std::to_string(report.max_zoom) + " / --minzoom " +
                    std::to_string(report.min_zoom) + ": the archive's " +
                    tileFormatName(options.format) + " tiles go from zoom 0 to " +
                    std::to_string(deepest));
    if (pmtiles && report.max_zoom + (mesh ? 1 : 0) > kPmtilesMaxZoom)
        throw Error(output + ": PMTiles holds zooms up to " + std::to_string(kPmtilesMaxZoom));

    std::vector<TileKey> keys = tileList(set, options, report.max_zoom);
    if (pmtiles)
        std::sort(keys.begin(), keys.end(), [&](TileKey a, TileKey b) {
            return pmtilesTileId(storedKey(options.format, a)) <
                   pmtilesTileId(storedKey(options.format, b));
        });
    const char* extension = mesh ? "terrain" : imageFormatName(options.image);
    const auto make = [&](TileKey k) -> std::optional<std::vector<uint8_t>> {
        if (mesh) {
            std::optional<ServedTile> t =
                set.terrain(k, kOctVertexNormals | kWaterMask | kMetadata);
            if (!t)
                return std::nullopt;
            const std::string gz = detail::gzipCompress(
                std::string_view(reinterpret_cast<const char*>(t->bytes.data()), t->bytes.size()));
            return std::vector<uint8_t>(gz.begin(), gz.end());
        }
        std::optional<RgbTile> t = set.terrainRgb(k, options.size, encoding, options.image);
        if (!t)
            return std::nullopt;
        return std::move(t->image);
    };
    const std::string metadata =
        mesh ? set.layerJson(false) : set.rgbTileJson(encoding, options.size, options.image, false);

    if (pmtiles) {
        AtomicOutput out(output);
        PmtilesWriter writer(out.fd(), output);
        makeInOrder(
            keys, report.threads, make,
            [&](size_t i, const std::optional<std::vector<uint8_t>>& tile) {
                if (!tile)
                    return;
                writer.add(pmtilesTileId(storedKey(options.format, keys[i])), *tile);
                ++report.tiles;
                report.bytes += tile->size();
            },
            options.progress);
        nlohmann::json meta = nlohmann::json::parse(metadata);
        meta["ridge:tiling"] = mesh ? "geographic-tms+1" : "xyz";
        PmtilesHeader header;
        header.tile_type = mesh                                ? PmtilesType::Unknown
                           : options.image == ImageFormat::Png ? PmtilesType::Png
                                                               : PmtilesType::Webp;
        header.tile_compression = mesh ? PmtilesCompression::Gzip : PmtilesCompression::None;
        header.min_zoom = report.min_zoom + (mesh ? 1 : 0);
        header.max_zoom = report.max_zoom + (mesh ? 1 : 0);
        header.bounds = clientBounds(set.info().extent);
        header.center_zoom = (report.min_zoom + report.max_zoom) / 2 + (mesh ? 1 : 0);
        header.center_lon = 0.5 * (header.bounds.west + header.bounds.east);
        header.center_lat = 0.5 * (header.bounds.south + header.bounds.north);
        writer.finish(header, meta.dump());
        report.output_bytes = writer.bytesWritten();
        out.commit();
    } else {
        TemporaryDirectory dir{fs::path(output)};
        makeInOrder(
            keys, report.threads, make,
            [&](size_t i, const std::optional<std::vector<uint8_t>>& tile) {
                if (!tile)
                    return;
                const fs::path file = dir.path() / keyPath(keys[i], extension);
                fs::create_directories(file.parent_path());
                writeFile(file, *tile);
                ++report.tiles;
                report.bytes += tile->size();
            },
            options.progress);
        writeFile(dir.path() / (mesh ? "layer.json" : "tiles.json"),
                  std::span(reinterpret_cast<const uint8_t*>(metadata.data()), metadata.size()));
        report.output_bytes = report.bytes + metadata.size();
        std::error_code ec;
        fs::rename(dir.path(), output, ec);
        if (ec)
            throw Error(output + ": cannot write: " + ec.message());
        dir.release();
    }
    reportDone(options.progress);
    report.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return report;
}

} // namespace ridge::web
