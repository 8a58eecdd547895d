// `ridge serve ARCHIVE... [--port 8080] [--bind 127.0.0.1]`: the archives as Cesium
// quantized-mesh tilesets over HTTP (web::TileService on web::HttpServer), with the CesiumJS
// and MapLibre pages at "/", until SIGINT or SIGTERM.
#include "commands.h"
#include "range_check.h"
#include "usage_error.h"

#include "ridge/core/error.h"
#include "ridge/io/crs_summary.h"
#include "ridge/web/http_server.h"

#include <fmt/core.h>

#include <cstdio>
#include <filesystem>
#include <thread>

namespace ridge::cli {

void ServeCommand::registerWith(CLI::App& app)
{
    command_ = app.add_subcommand(
        "serve", "Serve archives as Cesium quantized-mesh terrain over HTTP, with web pages");
    command_->add_option("archives", archives_, "Archives (.ridge); each is served at /NAME/")
        ->required();
    command_->add_option("--port", http_.port, "TCP port (0: any free port, printed)")
        ->capture_default_str()
        ->check(inIntegerRange("--port", 0, 65535));
    command_
        ->add_option("--bind", http_.bind,
                     "Address to listen on (0.0.0.0: every interface; default loopback only)")
        ->capture_default_str();
    command_->add_option("--threads", http_.threads, "Connections served at once")
        ->capture_default_str()
        ->check(inIntegerRange("--threads", 1, 1024));
    service_.tileset.samplers = int(std::clamp(std::thread::hardware_concurrency(), 1u, 64u));
    command_
        ->add_option("--samplers", service_.tileset.samplers,
                     "Tiles made at once per archive, each with its own decoded-patch cache "
                     "(default: the cores)")
        ->check(inIntegerRange("--samplers", 1, web::TilesetOptions::kMaxSamplers));
    command_
        ->add_option("--patch-cache", service_.tileset.cache_patches,
                     "Decoded patches each sampler keeps")
        ->capture_default_str()
        ->check(inIntegerRange("--patch-cache", 1, 1 << 20));
    command_->add_option("--cache-mb", cache_mb_, "Compressed tiles kept, MiB")
        ->capture_default_str()
        ->check(inRange("--cache-mb", ValueRange::closed(0.0, 1 << 20)));
    command_
        ->add_option("--cells", service_.tileset.cells,
                     "Grid cells a side a tile is sampled with (Cesium's heightmaps: 64)")
        ->capture_default_str()
        ->check(inIntegerRange("--cells", 1, 4096));
    command_
        ->add_option("--watermask", watermask_,
                     "Water in the watermask extension: none, nodata (off the archive or "
                     "kept nodata), water (and the archive's water flags)")
        ->capture_default_str()
        ->check(CLI::IsMember({"none", "nodata", "water"}));
    command_->add_option("--pages", pages_,
                         "Directory of web pages served at / (default: "
                         "ridge's web/ when built from source)");
    command_->add_flag("--no-pages", no_pages_, "Serve tiles only");
    command_
        ->add_option("--heights", heights_,
                     "Quantized-mesh heights: ellipsoid (Cesium's; geoid heights converted "
                     "through PROJ) or archive (as stored)")
        ->capture_default_str()
        ->check(CLI::IsMember({"ellipsoid", "archive"}));
    command_->add_option("--vertical-datum", vertical_datum_,
                         "The heights' vertical datum where the archive names none: an EPSG "
                         "code or a name, as build takes it (EPSG:5773, \"EGM96 height\")");
    command_->add_flag("--log", http_.log, "One line a request on stderr");
}

namespace {

// The EPSG code of the datum `text` names (as `ridge build --vertical-datum` takes it).
int verticalDatumCode(const std::string& text)
{
    const io::VerticalDatum datum = io::resolveVerticalDatum(text);
    if (!datum.epsg)
        throw UsageError("--vertical-datum '" + text.substr(0, 64) +
                         "': PROJ knows no vertical CRS of that name; give its EPSG code "
                         "(EPSG:5773 for EGM96 height)");
    return *datum.epsg;
}

} // namespace

int ServeCommand::run()
{
    service_.tileset.water = web::parseWaterSource(watermask_).value();
    service_.tileset.ellipsoidal = heights_ == "ellipsoid";
    if (!vertical_datum_.empty())
        service_.tileset.vertical_datum = verticalDatumCode(vertical_datum_);
    service_.tile_cache_bytes = size_t(cache_mb_ * 1024.0 * 1024.0);
    if (!no_pages_) {
        service_.pages_dir = pages_;
#ifdef RIDGE_WEB_PAGES_DIR
        if (pages_.empty() && std::filesystem::is_directory(RIDGE_WEB_PAGES_DIR))
            service_.pages_dir = RIDGE_WEB_PAGES_DIR;
#endif
    }
    web::TileService service(archives_, service_);
    web::HttpServer server(service, http_);
    const std::string host = http_.bind == "0.0.0.0" ? "127.0.0.1" : http_.bind;
    // The URL on stdout (a script reads the port of --port 0 there); the rest on stderr.
    std::printf("http://%s:%d/\n", host.c_str(), server.port());
    std::fflush(stdout);
    for (const auto& set : service.tilesets()) {
        const web::Tileset::Info info = set->info();
        std::fprintf(
            stderr, "ridge serve: %s -> http://%s:%d/%s/layer.json (zoom 0-%d, heights %s%s)\n",
            set->path().c_str(), host.c_str(), server.port(), set->name().c_str(), info.max_zoom,
            info.heights.c_str(), info.conversion.empty() ? "" : (": " + info.conversion).c_str());
        if (info.heights != "ellipsoid" && service_.tileset.ellipsoidal)
            std::fprintf(stderr,
                         "ridge serve: warning: %s's heights are above %s, not the ellipsoid "
                         "Cesium expects: name their datum with --vertical-datum EPSG:N to "
                         "convert them\n",
                         set->path().c_str(), info.heights.c_str());
    }
    std::fprintf(stderr, "ridge serve: pages %s; Ctrl-C stops\n",
                 service_.pages_dir.empty() ? "off" : service_.pages_dir.c_str());
    const int signal = web::runUntilSignalled(server);
    const web::TileService::Stats stats = service.stats();
    std::fprintf(stderr, "ridge serve: stopped%s; %llu tiles made, %llu cache hits\n",
                 signal ? " by a signal" : "", (unsigned long long)stats.tiles_made,
                 (unsigned long long)stats.cache_hits);
    return 0;
}

} // namespace ridge::cli
