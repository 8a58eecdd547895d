#include "ridge/web/tile_service.h"

#include "ridge/web/gzip.h"
#include "ridge/web/terrain_rgb.h"

#include "ridge/core/error.h"
#include "ridge/core/file_io.h"
#include "ridge/stream/lru_cache.h"

#include <nlohmann/json.hpp>
#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace ridge::web {

namespace {

constexpr size_t kMaxPathBytes = 1024;
constexpr size_t kMaxPageBytes = size_t(64) << 20; // a static file larger is not served
constexpr const char* kTerrainType = "application/vnd.quantized-mesh";
// Tiles whose URL names the archive's version never change; others are revalidated.
constexpr const char* kImmutable = "public, max-age=86400, immutable";
constexpr const char* kRevalidate = "no-cache";

WebResponse text(int status, std::string message)
{
    WebResponse r;
    r.status = status;
    r.body = std::move(message) + "\n";
    return r;
}

// A path of '/'-separated segments of [A-Za-z0-9._~@-], none empty, "." or ".."; the root "/".
bool wellFormedPath(std::string_view path)
{
    if (path.empty() || path[0] != '/' || path.size() > kMaxPathBytes)
        return false;
    if (path == "/")
        return true;
    std::string_view rest = path.substr(1);
    while (true) {
        const size_t slash = rest.find('/');
        const std::string_view segment = rest.substr(0, slash);
        if (segment.empty() || segment == "." || segment == "..")
            return false;
        for (const char c : segment)
            if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '-' ||
                  c == '~' || c == '@'))
                return false;
        if (slash == std::string_view::npos)
            return true;
        rest = rest.substr(slash + 1);
    }
}

// Whether an Accept-Encoding value takes gzip (a "gzip" or "*" coding without q=0).
bool acceptsGzip(std::string_view value)
{
    size_t at = 0;
    while (at <= value.size()) {
        size_t end = value.find(',', at);
        if (end == std::string_view::npos)
            end = value.size();
        std::string_view item = value.substr(at, end - at);
        const size_t semicolon = item.find(';');
        std::string_view coding = item.substr(0, semicolon);
        while (!coding.empty() && coding.front() == ' ')
            coding.remove_prefix(1);
        while (!coding.empty() && coding.back() == ' ')
            coding.remove_suffix(1);
        if (coding == "gzip" || coding == "*") {
            std::string params(semicolon == std::string_view::npos ? "" : item.substr(semicolon));
            params.erase(std::remove(params.begin(), params.end(), ' '), params.end());
            const bool refused = params.rfind(";q=0", 0) == 0 &&
                                 params.find_first_not_of("0.", 4) == std::string::npos;
            if (!refused)
                return true;
        }
        at = end + 1;
    }
    return false;
}

// Whether If-None-Match `value` ("*" or a list of entity tags, weak or strong) holds `etag`.
bool matches(std::string_view value, std::string_view etag)
{
    return value.find('*') != std::string_view::npos || value.find(etag) != std::string_view::npos;
}

std::string contentTypeOf(std::string_view path)
{
    static const std::pair<std::string_view, const char*> kTypes[] = {
        {".html", "text/html; charset=utf-8"},
        {".js", "text/javascript; charset=utf-8"},
        {".mjs", "text/javascript; charset=utf-8"},
        {".css", "text/css; charset=utf-8"},
        {".json", "application/json"},
        {".png", "image/png"},
        {".jpg", "image/jpeg"},
        {".svg", "image/svg+xml"},
        {".webp", "image/webp"},
        {".wasm", "application/wasm"},
        {".xml", "application/xml"},
        {".ktx2", "image/ktx2"},
        {".glb", "model/gltf-binary"},
        {".woff", "font/woff"},
        {".woff2", "font/woff2"},
    };
    for (const auto& [ext, type] : kTypes)
        if (path.size() >= ext.size() && path.substr(path.size() - ext.size()) == ext)
            return type;
    return "application/octet-stream";
}

// The value of `key` in a query "a=1&b=2" (empty when absent).
std::string_view queryParam(std::string_view query, std::string_view key)
{
    while (!query.empty()) {
        const size_t amp = query.find('&');
        const std::string_view pair = query.substr(0, amp);
        if (pair.size() > key.size() && pair.substr(0, key.size()) == key &&
            pair[key.size()] == '=')
            return pair.substr(key.size() + 1);
        query = amp == std::string_view::npos ? std::string_view() : query.substr(amp + 1);
    }
    return {};
}

std::string keyText(TileKey k)
{
    return std::to_string(k.z) + "/" + std::to_string(k.x) + "/" + std::to_string(k.y);
}

// Metres in a header, to the nanometre: a Terrarium step (1/256 m) reads exactly.
std::string formatMetres(double metres)
{
    char text[32];
    std::snprintf(text, sizeof text, "%.9g", metres);
    return text;
}

// A bound in a header, rounded up to the micrometre: what it states is never less than the
// bound.
std::string formatBound(double metres)
{
    char text[32];
    std::snprintf(text, sizeof text, "%.6f", std::ceil(metres * 1e6) / 1e6);
    return text;
}

std::string uniqueName(const std::string& path, const std::vector<std::unique_ptr<Tileset>>& sets)
{
    std::string stem = std::filesystem::path(path).filename().string();
    if (stem.size() > 6 && stem.substr(stem.size() - 6) == ".ridge")
        stem.resize(stem.size() - 6);
    std::string clean;
    for (const char c : stem)
        clean += std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' ? c : '_';
    if (clean.empty() || clean == "tilesets.json")
        clean = "terrain";
    std::string name = clean;
    for (int n = 2;
         std::any_of(sets.begin(), sets.end(), [&](const auto& s) { return s->name() == name; });
         ++n)
        name = clean + "-" + std::to_string(n);
    return name;
}

} // namespace

const std::string* WebResponse::header(std::string_view name) const
{
    for (const auto& [key, value] : headers)
        if (key == name)
            return &value;
    return nullptr;
}

void TileServiceOptions::validate() const
{
    tileset.validate();
    if (tile_cache_bytes > (size_t(1) << 40))
        throw Error("tile cache of " + std::to_string(tile_cache_bytes) + " bytes is past 1 TiB");
    if (!pages_dir.empty() && !std::filesystem::is_directory(pages_dir))
        throw Error(pages_dir + ": the pages directory is not a directory");
}

// A tile as sent (a quantized-mesh tile gzip-compressed, an image as encoded), with the
// headers that state what it claims.
struct TileService::CachedTile {
    std::shared_ptr<const std::string> bytes;
    std::string version;
    std::vector<std::pair<std::string, std::string>> headers;
};

struct TileService::Cache {
    explicit Cache(size_t bytes) : lru(bytes) {}
    std::mutex mutex; // guards everything here
    stream::LruCache<std::string, CachedTile> lru;
    std::map<std::string, std::shared_future<std::optional<CachedTile>>> in_flight;
    Stats stats;
};

TileService::TileService(const std::vector<std::string>& archives,
                         const TileServiceOptions& options)
    : options_(options), cache_(std::make_unique<Cache>(options.tile_cache_bytes))
{
    options_.validate();
    if (archives.empty())
        throw Error("no archive to serve");
    for (const std::string& path : archives)
        tilesets_.push_back(
            std::make_unique<Tileset>(uniqueName(path, tilesets_), path, options_.tileset));
}

TileService::~TileService() = default;

TileService::Stats TileService::stats() const
{
    std::lock_guard lock(cache_->mutex);
    Stats s = cache_->stats;
    s.cache_bytes = cache_->lru.weight();
    return s;
}

WebResponse TileService::handle(const WebRequest& request)
{
    WebResponse response;
    if (request.method != "GET" && request.method != "HEAD") {
        response = text(405, "405 method " + request.method.substr(0, 16) + " not allowed");
        response.headers.emplace_back("Allow", "GET, HEAD, OPTIONS");
    } else if (!wellFormedPath(request.path)) {
        response = text(400, "400 malformed path");
    } else {
        try {
            const std::string_view path = request.path;
            const size_t second = path.find('/', 1);
            const std::string_view first = path.substr(1, second - 1);
            Tileset* set = nullptr;
            for (const auto& s : tilesets_)
                if (s->name() == first)
                    set = s.get();
            const std::string_view rest =
                second == std::string_view::npos ? std::string_view() : path.substr(second + 1);
            if (path == "/tilesets.json") {
                response = tilesetsJson();
            } else if (set && rest == "layer.json") {
                response.content_type = "application/json";
                response.body = set->layerJson(true);
                response.headers.emplace_back("Cache-Control", kRevalidate);
            } else if (set && rest.size() > 8 && rest.substr(rest.size() - 8) == ".terrain") {
                const std::optional<TileKey> key = parseTilePath(rest, ".terrain");
                response =
                    key ? terrain(*set, *key, request) : text(400, "400 malformed tile path");
            } else if (set) {
                response = terrainRgb(*set, rest, request);
            } else {
                response = page(path);
            }
        } catch (const std::exception& e) {
            // The archive could not be read (a corrupt patch, a vanished file): refuse.
            std::fprintf(stderr, "ridge serve: %s: %s\n", request.path.c_str(), e.what());
            response = text(500, std::string("500 ") + e.what());
        }
    }
    // Every answer may be read by pages from any origin (tiles are public data).
    response.headers.emplace_back("Access-Control-Allow-Origin", "*");
    response.headers.emplace_back("Access-Control-Expose-Headers",
                                  "ETag, X-Ridge-Claimed-Error, X-Ridge-Version, "
                                  "X-Ridge-Step, X-Ridge-Archive-Error");
    if (response.content_length == 0)
        response.content_length = response.body.size();
    if (request.method == "HEAD")
        response.body.clear();
    return response;
}

WebResponse TileService::tilesetsJson()
{
    nlohmann::json list = nlohmann::json::array();
    for (const auto& s : tilesets_) {
        const Tileset::Info info = s->info();
        list.push_back(
            {{"name", s->name()},
             {"layer", s->name() + "/layer.json"},
             {"bounds", {info.extent.west, info.extent.south, info.extent.east, info.extent.north}},
             {"maxzoom", info.max_zoom},
             {"heights", info.heights},
             {"version", info.version}});
    }
    WebResponse r;
    r.content_type = "application/json";
    r.body = nlohmann::json{{"tilesets", list}}.dump(1);
    r.headers.emplace_back("Cache-Control", kRevalidate);
    return r;
}

std::optional<TileService::CachedTile>
TileService::cachedTile(const std::string& name,
                        const std::function<std::optional<CachedTile>()>& make)
{
    std::promise<std::optional<CachedTile>> promise;
    const std::shared_future<std::optional<CachedTile>> mine = promise.get_future().share();
    std::shared_future<std::optional<CachedTile>> wait;
    {
        std::lock_guard lock(cache_->mutex);
        if (const CachedTile* hit = cache_->lru.find(name)) {
            ++cache_->stats.cache_hits;
            return *hit;
        }
        auto flight = cache_->in_flight.find(name);
        if (flight != cache_->in_flight.end()) {
            wait = flight->second;
            ++cache_->stats.joined;
        } else {
            cache_->in_flight.emplace(name, mine);
        }
    }
    if (wait.valid())
        return wait.get(); // rethrows what the maker threw
    // This request makes it; others asking meanwhile wait for it.
    try {
        std::optional<CachedTile> made = make();
        {
            std::lock_guard lock(cache_->mutex);
            if (made) {
                ++cache_->stats.tiles_made;
                cache_->lru.insert(name, *made, made->bytes->size() + name.size() + 256);
            }
            cache_->in_flight.erase(name);
        }
        promise.set_value(made);
        return made;
    } catch (...) {
        {
            std::lock_guard lock(cache_->mutex);
            cache_->in_flight.erase(name);
        }
        promise.set_exception(std::current_exception());
        throw;
    }
}

WebResponse TileService::tileResponse(const CachedTile& tile, const std::string& name,
                                      const WebRequest& request, bool gzipped)
{
    // Tiles stored compressed are sent so to clients that take gzip, inflated to others.
    const bool send_gzip = gzipped && acceptsGzip(request.accept_encoding);
    // One strong tag per representation: the name holds the archive's version, the tile and
    // its options; the coding is added.
    const std::string tagged = name + (send_gzip ? "+gzip" : "");
    char etag[24];
    std::snprintf(etag, sizeof etag, "\"%016llx\"",
                  (unsigned long long)fnv1a64(tagged.data(), tagged.size()));
    WebResponse r;
    r.headers = tile.headers;
    r.headers.emplace_back("ETag", etag);
    r.headers.emplace_back("Vary", gzipped ? "Accept, Accept-Encoding" : "Accept");
    const bool pinned = queryParam(request.query, "v") == tile.version;
    r.headers.emplace_back("Cache-Control", pinned ? kImmutable : kRevalidate);
    r.headers.emplace_back("X-Ridge-Version", tile.version);
    if (!request.if_none_match.empty() && matches(request.if_none_match, etag)) {
        r.status = 304;
        return r;
    }
    if (send_gzip)
        r.headers.emplace_back("Content-Encoding", "gzip");
    r.body = gzipped && !send_gzip ? detail::gzipDecompress(*tile.bytes, size_t(256) << 20)
                                   : *tile.bytes;
    return r;
}

WebResponse TileService::terrain(Tileset& set, TileKey key, const WebRequest& request)
{
    if (!GeographicTms::valid(key))
        return text(404, "404 no tile " + keyText(key) + " in the geographic tiling");
    const unsigned extensions = parseAcceptedExtensions(request.accept);
    const std::string name = set.info().version + "/" + set.name() + "/" + keyText(key) +
                             ".terrain+" + std::to_string(extensions);
    const std::optional<CachedTile> tile = cachedTile(name, [&]() -> std::optional<CachedTile> {
        std::optional<ServedTile> made = set.terrain(key, extensions);
        if (!made)
            return std::nullopt;
        CachedTile t;
        t.bytes = std::make_shared<const std::string>(detail::gzipCompress(std::string_view(
            reinterpret_cast<const char*>(made->bytes.data()), made->bytes.size())));
        t.version = made->version;
        t.headers.emplace_back("X-Ridge-Claimed-Error", formatBound(made->claimed_error));
        return t;
    });
    if (!tile)
        return text(404, "404 tile " + keyText(key) + " is not available in " + set.name());
    WebResponse r = tileResponse(*tile, name, request, true);
    r.content_type = kTerrainType;
    if (extensions)
        r.content_type += ";extensions=" + extensionNames(extensions);
    return r;
}

WebResponse TileService::terrainRgb(Tileset& set, std::string_view rest, const WebRequest& request)
{
    // ENCODING[@2x].json, or ENCODING[@2x]/Z/X/Y.png|webp.
    const size_t slash = rest.find('/');
    std::string_view layer = rest.substr(0, slash);
    const bool tilejson = slash == std::string_view::npos;
    if (tilejson) {
        if (!layer.ends_with(".json"))
            return text(404, "404 no such resource in tileset " + set.name());
        layer.remove_suffix(5);
    }
    int size = 256;
    if (layer.ends_with("@2x")) {
        size = 512;
        layer.remove_suffix(3);
    }
    const std::optional<RgbEncoding> encoding = parseRgbEncoding(layer);
    if (!encoding)
        return text(404, "404 no such resource in tileset " + set.name());
    if (tilejson) {
        const ImageFormat format =
            queryParam(request.query, "format") == "webp" ? ImageFormat::Webp : ImageFormat::Png;
        WebResponse r;
        r.content_type = "application/json";
        r.body = set.rgbTileJson(*encoding, size, format);
        r.headers.emplace_back("Cache-Control", kRevalidate);
        return r;
    }
    const std::string_view tile_path = rest.substr(slash + 1);
    ImageFormat format = ImageFormat::Png;
    std::optional<TileKey> key = parseTilePath(tile_path, ".png");
    if (!key) {
        format = ImageFormat::Webp;
        key = parseTilePath(tile_path, ".webp");
    }
    if (!key)
        return text(400, "400 malformed tile path (Z/X/Y.png or Z/X/Y.webp)");
    if (!WebMercatorXyz::valid(*key))
        return text(404, "404 no tile " + keyText(*key) + " in the Web Mercator tiling");
    const std::string name = set.info().version + "/" + set.name() + "/" + std::string(layer) +
                             "@" + std::to_string(size) + "/" + keyText(*key) + "." +
                             imageFormatName(format);
    const std::optional<CachedTile> tile = cachedTile(name, [&]() -> std::optional<CachedTile> {
        std::optional<RgbTile> made = set.terrainRgb(*key, size, *encoding, format);
        if (!made)
            return std::nullopt;
        CachedTile t;
        t.bytes = std::make_shared<const std::string>(made->image.begin(), made->image.end());
        t.version = set.info().version;
        t.headers.emplace_back("X-Ridge-Step", formatMetres(made->step));
        t.headers.emplace_back("X-Ridge-Archive-Error", formatBound(made->archive_error));
        return t;
    });
    if (!tile)
        return text(404, "404 tile " + keyText(*key) + " is not available in " + set.name());
    WebResponse r = tileResponse(*tile, name, request, false);
    r.content_type = imageContentType(format);
    return r;
}

WebResponse TileService::page(std::string_view path) const
{
    if (options_.pages_dir.empty())
        return text(404, "404 not found (no pages are served)");
    std::filesystem::path file = std::filesystem::path(options_.pages_dir) /
                                 std::string(path == "/" ? "index.html" : path.substr(1));
    std::error_code ec;
    if (std::filesystem::is_directory(file, ec))
        file /= "index.html";
    struct stat st {};
    if (::stat(file.c_str(), &st) != 0 || !S_ISREG(st.st_mode))
        return text(404, "404 not found");
    if (size_t(st.st_size) > kMaxPageBytes)
        return text(404, "404 not served (larger than 64 MiB)");
    std::ifstream in(file, std::ios::binary);
    std::ostringstream body;
    body << in.rdbuf();
    if (!in && !in.eof())
        return text(500, "500 cannot read the page");
    WebResponse r;
    r.content_type = contentTypeOf(file.string());
    r.body = std::move(body).str();
    r.headers.emplace_back("Cache-Control", "no-cache");
    return r;
}

} // namespace ridge::web
