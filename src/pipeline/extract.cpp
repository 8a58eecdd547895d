#include "ridge/pipeline/extract.h"

#include "ridge/archive/archive_reader.h"
#include "ridge/core/atomic_output.h"
#include "ridge/core/file_identity.h"
#include "ridge/core/parameter_check.h"
#include "ridge/io/raster_writer.h"
#include "ridge/pipeline/level_decoder.h"

#include "ridge/core/error.h"

#include <cmath>
#include <cstdint>
#include <limits>

namespace ridge {

namespace {

// The source's georeference as the archive recorded it (checked when the reader opened it).
io::GeoReference storedGeoReference(const archive::ArchiveReader& reader)
{
    const archive::GeoreferenceMetadata& stored = reader.metadata().georeference;
    io::GeoReference geo;
    geo.crs_wkt = stored.crs_wkt;
    geo.geographic = stored.geographic;
    geo.vertical_units = stored.vertical_units;
    geo.spacing_from_user = stored.spacing_from_user;
    if (stored.geotransform) {
        geo.has_geotransform = true;
        geo.geotransform = *stored.geotransform;
    }
    geo.spacing_x = reader.header().spacing_x;
    geo.spacing_y = reader.header().spacing_y;
    return geo;
}

} // namespace

void ExtractOptions::validate() const
{
    checkParameter("level", int64_t{level}, -1, kMaxLevel);
    if (nodata && !std::isnan(*nodata))
        checkParameter("nodata", *nodata, ValueRange::any());
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
    refuseOutputOverInput(output, {archive_path});
    checkOutputWritable(output); // before the work, not after it
    const archive::ArchiveReader reader(archive_path);
    const PyramidGeometry& g = reader.geometry();
    const int level = resolveLevel(reader, options.level);
    ExtractWindow w = options.window.value_or(ExtractWindow{});
    if (!options.window && level < g.levelCount())
        w = {0, 0, g.validLevelWidth(level), g.validLevelHeight(level)};
    std::vector<uint8_t> valid;
    const CodeGrid grid = decodeLevelWindow(reader, level, w.x, w.y, w.width, w.height,
                                            subProgress(options.progress, 0.0, 0.8), &valid);

    std::vector<float> metres = toMetres(grid, reader.quantization());
    std::optional<double> nodata;
    if (!valid.empty()) {
        nodata = options.nodata ? options.nodata : reader.metadata().source.nodata;
        if (!nodata)
            nodata = std::numeric_limits<double>::quiet_NaN();
        const float value = static_cast<float>(*nodata);
        for (size_t i = 0; i < metres.size(); ++i) {
            if (!valid[i])
                metres[i] = value;
            else if (metres[i] == value) // never for NaN
                throw Error(output + ": nodata value " + std::to_string(*nodata) +
                            " equals the height of sample (" + std::to_string(i % grid.width) +
                            ", " + std::to_string(i / grid.width) +
                            "): choose another nodata value");
        }
    }

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
    io::writeGeoTiff(output, metres.data(), grid.width, grid.height, geo, nodata);
    reportDone(options.progress); // published: too late to cancel
}

} // namespace ridge
