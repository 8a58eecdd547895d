#include "ridge/pipeline/extract.h"

#include "ridge/archive/archive_reader.h"
#include "ridge/core/parameter_check.h"
#include "ridge/io/raster_writer.h"
#include "ridge/pipeline/level_decoder.h"

#include <nlohmann/json.hpp>

#include <cstdint>

namespace ridge {

namespace {

// Reads the source's georeference back from the archive metadata.
io::GeoReference storedGeoReference(const archive::ArchiveReader& reader)
{
    io::GeoReference geo;
    const nlohmann::json meta = nlohmann::json::parse(reader.metadataJson(), nullptr, false);
    if (meta.is_discarded() || !meta.contains("georeference"))
        return geo;
    const nlohmann::json& g = meta["georeference"];
    geo.crs_wkt = g.value("crs_wkt", "");
    geo.geographic = g.value("geographic", false);
    if (g.contains("geotransform") && g["geotransform"].is_array() && g["geotransform"].size() == 6) {
        geo.has_geotransform = true;
        for (int k = 0; k < 6; ++k)
            geo.geotransform[k] = g["geotransform"][k].get<double>();
    }
    geo.spacing_x = reader.header().spacing_x;
    geo.spacing_y = reader.header().spacing_y;
    return geo;
}

} // namespace

void ExtractOptions::validate() const
{
    checkParameter("level", int64_t{level}, -1, kMaxLevel);
    if (!window)
        return;
    checkParameter("window x", int64_t{window->x}, 0, INT32_MAX);
    checkParameter("window y", int64_t{window->y}, 0, INT32_MAX);
    checkParameter("window width", int64_t{window->width}, 1, INT32_MAX);
    checkParameter("window height", int64_t{window->height}, 1, INT32_MAX);
}

void extractLevel(const std::string& archive_path, const std::string& output,
                  const ExtractOptions& options)
{
    options.validate();
    const archive::ArchiveReader reader(archive_path);
    const PyramidGeometry& g = reader.geometry();
    const int level = resolveLevel(reader, options.level);
    ExtractWindow w = options.window.value_or(ExtractWindow{});
    if (!options.window && level < g.levelCount())
        w = {0, 0, g.validLevelWidth(level), g.validLevelHeight(level)};
    const CodeGrid grid = decodeLevelWindow(reader, level, w.x, w.y, w.width, w.height,
                                            subProgress(options.progress, 0.0, 0.8));

    const std::vector<float> metres = toMetres(grid, reader.quantization());

    io::GeoReference geo = storedGeoReference(reader);
    if (geo.has_geotransform) {
        // Output pixel (i', j') centre = finest sample ((x+i') s, (y+j') s) centre.
        auto& gt = geo.geotransform;
        const double s = double(g.step(level));
        const double a = w.x * s + 0.5 - 0.5 * s;
        const double b = w.y * s + 0.5 - 0.5 * s;
        gt[0] += a * gt[1] + b * gt[2];
        gt[3] += a * gt[4] + b * gt[5];
        for (int k : {1, 2, 4, 5})
            gt[k] *= s;
    }
    io::writeGeoTiff(output, metres.data(), grid.width, grid.height, geo);
    reportProgress(options.progress, 1.0);
}

} // namespace ridge
