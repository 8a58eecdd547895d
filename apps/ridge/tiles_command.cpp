// `ridge tiles ARCHIVE -o DIR|FILE.pmtiles --format quantized-mesh|terrain-rgb|terrarium
// [--minzoom N] [--maxzoom N]`: the tiles `ridge serve` answers, written for static hosting
// (web::writeTiles), with GDAL-style progress.
#include "command_text.h"
#include "commands.h"
#include "range_check.h"
#include "terminal.h"

#include "ridge/core/error.h"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <cstdio>

namespace ridge::cli {

void TilesCommand::registerWith(CLI::App& app)
{
    command_ = app.add_subcommand(
        "tiles", "Write an archive's web tiles (quantized-mesh or terrain-RGB) to a directory "
                 "or a PMTiles file, for static hosting");
    command_->add_option("archive", archive_, "Archive (.ridge)")->required();
    command_
        ->add_option("-o,--output", output_,
                     "Output: a new directory, or a file ending in .pmtiles (replaced)")
        ->required();
    command_
        ->add_option("--format", format_,
                     "quantized-mesh (Cesium, geographic TMS), terrain-rgb (Mapbox encoding) or "
                     "terrarium (both Web Mercator XYZ)")
        ->capture_default_str()
        ->check(CLI::IsMember({"quantized-mesh", "terrain-rgb", "terrarium"}));
    command_->add_option("--minzoom", options_.min_zoom, "First zoom written")
        ->capture_default_str()
        ->check(inIntegerRange("--minzoom", 0, web::kMaxTileZoom));
    command_
        ->add_option("--maxzoom", options_.max_zoom,
                     "Last zoom written (default: the deepest the archive's spacing supports)")
        ->check(inIntegerRange("--maxzoom", 0, web::kMaxTileZoom));
    command_->add_option("--image", image_, "Terrain-RGB image format: png or webp (lossless)")
        ->capture_default_str()
        ->check(CLI::IsMember({"png", "webp"}));
    command_->add_option("--size", options_.size, "Terrain-RGB tile size, pixels: 256 or 512")
        ->capture_default_str()
        ->check(CLI::IsMember({256, 512}));
    command_->add_option("--threads", options_.threads, "Tiles made at once (default: the cores)")
        ->check(inIntegerRange("--threads", 1, web::TilesetOptions::kMaxSamplers));
    command_
        ->add_option("--cells", options_.tileset.cells,
                     "Quantized-mesh: grid cells a side a tile is sampled with")
        ->capture_default_str()
        ->check(inIntegerRange("--cells", 1, 4096));
    command_
        ->add_option("--watermask", watermask_,
                     "Quantized-mesh water mask: none, nodata or water (see ridge serve)")
        ->capture_default_str()
        ->check(CLI::IsMember({"none", "nodata", "water"}));
    command_->add_flag("--json", json_, "Print a JSON report on stdout");
    addCommonFlags(command_, quiet_);
}

int TilesCommand::run()
{
    options_.format = web::parseTileFormat(format_).value();
    options_.image = image_ == "webp" ? web::ImageFormat::Webp : web::ImageFormat::Png;
    options_.tileset.water = web::parseWaterSource(watermask_).value();
    options_.progress = terminalProgress(quiet_ || json_);
    const web::TileWriteReport r = web::writeTiles(archive_, output_, options_);
    const double rate = r.seconds > 0 ? double(r.tiles) / r.seconds : 0.0;
    if (json_) {
        const nlohmann::json doc = {
            {"archive", archive_},      {"output", output_},
            {"format", format_},        {"minzoom", r.min_zoom},
            {"maxzoom", r.max_zoom},    {"tiles", r.tiles},
            {"tile_bytes", r.bytes},    {"output_bytes", r.output_bytes},
            {"seconds", r.seconds},     {"threads", r.threads},
            {"tiles_per_second", rate}, {"tiles_per_second_per_thread", rate / r.threads}};
        std::printf("%s\n", doc.dump(1).c_str());
    } else if (!quiet_) {
        std::fprintf(stderr,
                     "%s: %llu %s tiles, zoom %d-%d, %s in %.1f s (%.0f tiles/s on %d "
                     "threads)\n",
                     output_.c_str(), (unsigned long long)r.tiles, format_.c_str(), r.min_zoom,
                     r.max_zoom, humanBytes(r.output_bytes).c_str(), r.seconds, rate, r.threads);
    }
    return 0;
}

} // namespace ridge::cli
