#pragma once
// What `ridge serve` answers, as plain C++ (no sockets; http_server.h puts it on HTTP):
// routes, status codes, content types, compression, validators and caching for the
// tilesets it holds, and the static pages.
//
// Routes (GET and HEAD):
//   /                                 the pages' index (web/index.html), when pages are served
//   /tilesets.json                    the tilesets: name, layer URL, bounds, zooms
//   /NAME/layer.json                  Tileset::layerJson (no-cache: it names the version)
//   /NAME/Z/X/Y.terrain[?v=VERSION]   a quantized-mesh tile, gzip
//   /NAME/ENC[@2x].json[?format=webp] TileJSON of terrain-RGB (ENC mapbox or terrarium;
//                                     @2x 512 px tiles), for MapLibre raster-dem sources
//   /NAME/ENC[@2x]/Z/X/Y.png|.webp    a terrain-RGB tile (terrain_rgb.h), Web Mercator XYZ
//   /FILE under the pages' directory  static files (html, js, css, json, images, wasm)
// Status: 400 for a path that is not one of these shapes (bad characters, "..", numbers that
// do not parse), 404 for a well-formed path naming nothing (an unknown tileset, a tile outside
// the tiling or not available), 405 for another method, 304 when If-None-Match holds the
// ETag, 500 when the archive cannot be read (a corrupt patch: the tile is refused, never sent
// corrupt).
//
// Tiles are kept, compressed, in a cache bounded in bytes, and one request makes a tile while
// others asking for the same one wait for it (no tile is made twice at once).
#include "ridge/web/tileset.h"

#include <cstddef>
#include <functional>
#include <future>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace ridge::web {

struct WebRequest {
    std::string method = "GET";
    std::string path;   // without the query
    std::string query;  // after '?', "key=value&..." (TileService reads v and format)
    std::string accept; // header values, may be empty
    std::string accept_encoding;
    std::string if_none_match;
};

struct WebResponse {
    int status = 200;
    std::string content_type = "text/plain; charset=utf-8";
    std::string body; // empty for HEAD and 304 (content_length then says the size)
    size_t content_length = 0;
    std::vector<std::pair<std::string, std::string>> headers; // besides type and length
    const std::string* header(std::string_view name) const;
};

struct TileServiceOptions {
    TilesetOptions tileset;
    size_t tile_cache_bytes = size_t(64) << 20; // compressed tiles kept
    std::string pages_dir;                      // served at "/" when not empty (web/)
    void validate() const;
};

class TileService {
  public:
    // Opens each archive as a tileset named by its file name without ".ridge" (made unique
    // with "-2", "-3" ...). Throws ridge::Error naming the archive that cannot be opened, or
    // for no archive at all or a pages directory that is not one.
    TileService(const std::vector<std::string>& archives, const TileServiceOptions& options);
    ~TileService();

    const std::vector<std::unique_ptr<Tileset>>& tilesets() const { return tilesets_; }
    // Thread-safe.
    WebResponse handle(const WebRequest& request);

    struct Stats {
        uint64_t tiles_made = 0; // tiles made (not found in the cache)
        uint64_t cache_hits = 0; // requests answered from the cache
        uint64_t joined = 0;     // requests that waited for the same tile made by another
        uint64_t cache_bytes = 0;
    };
    Stats stats() const;

  private:
    struct CachedTile;
    WebResponse terrain(Tileset& set, TileKey key, const WebRequest& request);
    WebResponse terrainRgb(Tileset& set, std::string_view rest, const WebRequest& request);
    WebResponse page(std::string_view path) const;
    WebResponse tilesetsJson();
    // The tile named `name` (the archive's version, the tile, its options), from the cache
    // or made by `make` (nullopt: not available) — once, whoever asks meanwhile.
    std::optional<CachedTile> cachedTile(const std::string& name,
                                         const std::function<std::optional<CachedTile>()>& make);
    // The response for a tile: ETag, validators, caching, compression.
    static WebResponse tileResponse(const CachedTile& tile, const std::string& name,
                                    const WebRequest& request, bool gzipped);

    TileServiceOptions options_;
    std::vector<std::unique_ptr<Tileset>> tilesets_;
    struct Cache;
    std::unique_ptr<Cache> cache_;
};

} // namespace ridge::web
