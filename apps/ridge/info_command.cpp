// `ridge info ARCHIVE`: what an archive holds, in gdalinfo's words where it has them (the
// band's type and NoData, the CRS's EPSG code, the corner coordinates).
#include "command_text.h"
#include "commands.h"

#include "ridge/core/json_text.h"
#include "ridge/io/geographic.h"
#include "ridge/pipeline/info.h"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <cmath>

namespace ridge::cli {

namespace {

// gdalinfo's "Corner Coordinates:" block: CRS numbers as it formats them, then DMS lon/lat.
void printCorners(const ArchiveInfo& info)
{
    if (info.corners.empty())
        return;
    fmt::print("Corner Coordinates:\n");
    for (const CornerInfo& c : info.corners) {
        const bool degrees = std::abs(c.x) < 181 && std::abs(c.y) < 91;
        std::string line = degrees ? fmt::format("{:<11} ({:12.7f},{:12.7f})", c.name, c.x, c.y)
                                   : fmt::format("{:<11} ({:12.3f},{:12.3f})", c.name, c.x, c.y);
        if (c.has_lon_lat)
            line += fmt::format(" ({},{})", io::formatDms(c.longitude, true),
                                io::formatDms(c.latitude, false));
        fmt::print("{}\n", line);
    }
    if (!info.lon_lat_note.empty())
        fmt::print("(no longitude/latitude: {})\n", info.lon_lat_note);
}

// gdalinfo -json's cornerCoordinates (CRS) and wgs84Extent, plus ridge's lon/lat per corner.
void addCornersJson(const ArchiveInfo& info, nlohmann::json& j)
{
    if (info.corners.empty())
        return;
    const char* keys[] = {"upperLeft", "lowerLeft", "upperRight", "lowerRight", "center"};
    nlohmann::json crs = nlohmann::json::object(), lon_lat = nlohmann::json::object();
    for (size_t k = 0; k < info.corners.size() && k < 5; ++k) {
        const CornerInfo& c = info.corners[k];
        crs[keys[k]] = {c.x, c.y};
        if (c.has_lon_lat)
            lon_lat[keys[k]] = {c.longitude, c.latitude};
    }
    j["cornerCoordinates"] = crs;
    if (lon_lat.size() == info.corners.size())
        j["cornerLonLat"] = lon_lat;
}

// `--bytes`: every region and part with its share of the file.
void printByteAccount(const ByteAccount& b)
{
    const double total = double(b.total());
    auto row = [&](const std::string& what, uint64_t bytes) {
        fmt::print("  {:<34} {:>12} {:>6.2f} %\n", what, bytes, 100.0 * double(bytes) / total);
    };
    fmt::print("\nBytes ({} in all):\n", b.total());
    row("header", b.header);
    row("index", b.index);
    row("metadata", b.metadata);
    row("codec tables", b.codec_tables);
    for (size_t l = 0; l < b.levels.size(); ++l) {
        const ByteAccount::Level& level = b.levels[l];
        row(fmt::format("level {} codec payloads", l), level.payload);
        if (level.block_errors)
            row(fmt::format("level {} block errors", l), level.block_errors);
        row(fmt::format("level {} validity masks", l), level.validity);
        row(fmt::format("level {} sample flags", l), level.sample_flags);
    }
}

} // namespace

void Commands::registerInfo(CLI::App& app)
{
    info_ =
        app.add_subcommand("info", "Describe an archive: geometry, levels, codec, georeference");
    info_->add_option("archive", archive_, "Archive (.ridge)")->required();
    info_->add_flag("--json", json_, "Machine-readable output");
    info_->add_flag("--bytes", info_bytes_,
                    "Where the bytes go: index, metadata, codec tables, and each level's blobs "
                    "by part (block errors, validity masks, sample flags, codec payloads); reads "
                    "every blob");
}

int Commands::runInfo()
{
    const ArchiveInfo info = readArchiveInfo(archive_, info_bytes_);
    if (json_) {
        nlohmann::json j = {
            {"path", info.path},
            {"format_version", info.format_version},
            {"file_bytes", info.file_bytes},
            {"width", info.width},
            {"height", info.height},
            {"patch_size", info.patch_size},
            {"level_count", info.level_count},
            {"block_cells", info.block_cells},
            {"block_levels", info.block_levels},
            {"patch_count", info.patch_count},
            {"codec", info.codec},
            {"filter", info.filter},
            {"height_scale", info.height_scale},
            {"height_offset", info.height_offset},
            {"quantization_error", info.quantization_error},
            {"spacing_x", info.spacing_x},
            {"spacing_y", info.spacing_y},
            {"min_height", info.min_height},
            {"max_height", info.max_height},
            {"metadata", nlohmann::json::parse(info.metadata_json)}, // checked by the reader
            {"quantization_step", info.quantization_step},
            {"exact", info.exact},
            {"crs_name", info.crs_name},
            {"epsg", info.epsg ? nlohmann::json(*info.epsg) : nlohmann::json()},
            {"vertical_datum", nullptr},
        };
        // gdalinfo -json's band entry, for the one band the archive holds.
        nlohmann::json band = {{"band", info.band}, {"type", info.data_type}};
        if (info.nodata)
            band["noDataValue"] = *info.nodata;
        j["bands"] = nlohmann::json::array({band});
        if (const auto& datum = info.vertical_datum) {
            j["vertical_datum"] = {{"name", datum->name}, {"from", datum->origin}};
            j["vertical_datum"]["epsg"] =
                datum->epsg ? nlohmann::json(*datum->epsg) : nlohmann::json();
        }
        addCornersJson(info, j);
        for (const LevelInfo& l : info.levels)
            j["levels"].push_back({{"level", l.level},
                                   {"step", l.step},
                                   {"width", l.width},
                                   {"height", l.height},
                                   {"patches_x", l.patches_x},
                                   {"patches_y", l.patches_y},
                                   {"bytes", l.bytes},
                                   {"max_err", l.max_err},
                                   {"max_err_appr", l.max_err_appr},
                                   {"level_bound", l.level_bound}});
        if (const auto& b = info.bytes) {
            j["bytes"] = {{"header", b->header},
                          {"index", b->index},
                          {"metadata", b->metadata},
                          {"codec_tables", b->codec_tables}};
            for (const ByteAccount::Level& l : b->levels)
                j["bytes"]["levels"].push_back({{"block_errors", l.block_errors},
                                                {"validity", l.validity},
                                                {"sample_flags", l.sample_flags},
                                                {"payload", l.payload}});
        }
        fmt::print("{}\n", jsonText(j));
        return 0;
    }
    const archive::SourceMetadata& source = info.metadata.source;
    const archive::GeoreferenceMetadata& geo = info.metadata.georeference;
    fmt::print("Archive: {} (ridge format v{}, {})\n", info.path, info.format_version,
               humanBytes(info.file_bytes));
    fmt::print("Source: {} ({} voids filled, {} kept as nodata, --fill-voids {})\n", source.path,
               source.voids_filled, source.voids_kept, source.fill_voids);
    // gdalinfo's words for the band.
    fmt::print("Band {} Type={}, NoData Value={}\n", info.band, info.data_type,
               info.nodata ? fmt::format("{:.17g}", *info.nodata) : std::string("none"));
    fmt::print("Grid: {} x {} samples, spacing {:.3f} x {:.3f} m{}\n", info.width, info.height,
               info.spacing_x, info.spacing_y,
               geo.spacing_from_user ? " (given with --spacing or default 1, no georeferencing)"
                                     : "");
    fmt::print("Heights: {:.2f} .. {:.2f} m, metres = {:g} + {:g} * code, {}\n", info.min_height,
               info.max_height, info.height_offset, info.height_scale,
               info.exact ? std::string("exact (every source sample is its code's height)")
                          : fmt::format("quantized: {} heights to a step of {}, each within {}",
                                        info.data_type, humanMetres(info.quantization_step),
                                        humanMetres(info.quantization_error)));
    if (const auto& datum = info.vertical_datum)
        fmt::print("Vertical datum: {}{}, from {}\n", datum->name,
                   datum->epsg ? fmt::format(" (EPSG:{})", *datum->epsg) : std::string(),
                   datum->origin == "source CRS" ? std::string("the source's CRS") : datum->origin);
    else
        fmt::print("Vertical datum: unknown (the source's CRS states none; build "
                   "--vertical-datum NAME_OR_EPSG records one)\n");
    // Water (format v4): how it was decided and how much of the grid it is.
    const archive::WaterMetadata& water = info.metadata.water;
    if (info.format_version < 4)
        fmt::print("Water: not stored (format v{}: drawn where the decoded height is <= 0 m)\n",
                   info.format_version);
    else
        fmt::print("Water: {} samples ({:.1f} %), {}{}\n", water.samples,
                   100.0 * double(water.samples) / (double(info.width) * double(info.height)),
                   water.sea_level ? fmt::format("at or below {:g} m", *water.sea_level)
                                   : std::string("no sea level"),
                   water.layer ? fmt::format(", and the layer {}", *water.layer) : std::string());
    fmt::print("Patches: {}x{} samples, {} levels, {} patches, tessellation blocks {}x{} cells (λ "
               "for d = 1..{})\n",
               info.patch_size, info.patch_size, info.level_count, info.patch_count,
               info.block_cells, info.block_cells, info.block_levels);
    fmt::print("Codec: {}, level filter: {}\n", info.codec, info.filter);
    if (geo.geotransform) {
        const std::array<double, 6>& gt = *geo.geotransform;
        fmt::print("Geotransform: ({:.9g}, {:.9g}, {:.9g}, {:.9g}, {:.9g}, {:.9g})\n", gt[0], gt[1],
                   gt[2], gt[3], gt[4], gt[5]);
    }
    if (geo.crs_wkt.empty())
        fmt::print("CRS: none\n");
    else if (!info.crs_note.empty())
        fmt::print("CRS: unreadable ({})\n", info.crs_note);
    else
        fmt::print("CRS: {}{}\n", info.crs_name,
                   info.epsg ? fmt::format(" (EPSG:{})", *info.epsg) : std::string());
    printCorners(info);
    fmt::print("\n{:>5} {:>6} {:>13} {:>11} {:>11} {:>12} {:>12}\n", "level", "step", "samples",
               "patches", "bytes", "max Err(P)", "δ_l");
    for (const LevelInfo& l : info.levels)
        fmt::print("{:>5} {:>6} {:>13} {:>11} {:>11} {:>10.3f} m {:>10.3f} m\n", l.level, l.step,
                   fmt::format("{}x{}", l.width, l.height),
                   fmt::format("{}x{}", l.patches_x, l.patches_y), humanBytes(l.bytes), l.max_err,
                   l.level_bound);
    if (info.bytes)
        printByteAccount(*info.bytes);
    return 0;
}

} // namespace ridge::cli
