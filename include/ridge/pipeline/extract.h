#pragma once
// `ridge extract`: one level (or a window of it) back to a georeferenced raster, in any GDAL
// format that writes, like gdal_translate.
#include "ridge/core/progress.h"

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace ridge {

// A window in level samples (gdal_translate's -srcwin): x, y of its first sample, its size.
struct ExtractWindow {
    int x = 0, y = 0, width = 0, height = 0; // level sample units
};

// A window in the archive's CRS (gdal_translate's -projwin): upper-left and lower-right
// corners. Turned into level samples as gdal_translate does with nearest resampling:
// x = floor((ulx - gt0) / gt1 + 0.001), width = floor((lrx - ulx) / gt1 + 0.5), and likewise
// in y, against the extracted level's geotransform.
struct ProjectionWindow {
    double ulx = 0, uly = 0, lrx = 0, lry = 0;
};

struct ExtractOptions {
    static constexpr int kMaxLevel = 62; // PatchId levels; -1 means the finest

    int level = -1;                          // -1: the finest level
    std::optional<ExtractWindow> window;     // default: the level's whole valid extent
    std::optional<ProjectionWindow> projwin; // instead of `window`
    // GDAL sample type ("Int16", "Float32", ...). Default: the source's (archive metadata
    // source.data_type) when it is a floating-point type whose range holds the heights (they
    // come back to the source's own precision) or an integer type that holds every extracted
    // height exactly; else Float32 when that gives every code back, else Float64. A type given here
    // is used as asked: integer types round to the nearest integer
    // (ExtractReport::max_rounding_error says by how much); heights outside the type's range are
    // refused.
    std::optional<std::string> output_type;
    std::string output_format = "GTiff";       // any GDAL driver that can Create or CreateCopy
    std::vector<std::string> creation_options; // "NAME=VALUE", passed to the driver
    // The band's nodata value; must be held by the output type and be no extracted height.
    // Samples the archive keeps as nodata (validity masks, io::VoidFill) are written as it.
    // Unset: declared only when the window holds kept nodata, as the source's declared
    // nodata if the type holds it, else NaN (floating-point types) or the type's lowest value.
    std::optional<double> nodata_value;
    Progress progress;

    // Throws ridge::Error naming the first field outside its range: level in [-1, kMaxLevel],
    // window x, y >= 0 and width, height >= 1, projwin finite with ulx != lrx and uly != lry,
    // not both window and projwin, nodata_value finite (whether they fit the level, the type
    // and the driver is checked against the archive).
    void validate() const;
};

// What was written, for the command line to report.
struct ExtractReport {
    int level = 0;
    ExtractWindow window;          // in level samples
    std::string output_type;       // GDAL's name
    std::string type_reason;       // why that type ("the source's", "requested", ...)
    double max_rounding_error = 0; // metres between a height and the value written
    std::optional<std::array<double, 6>> geotransform; // of the output
};

// Writes the window of the level in metres, kept nodata as `nodata_value`. The geotransform is the
// source's, scaled by the level's step and shifted so that every output pixel centre sits on its
// finest-grid sample's centre (at the finest level: exactly gdal_translate's for the same window).
// Throws ridge::Error (options are validated first, the format and the window before any
// decoding); leaves nothing at `output` (or its side-car files) on failure, and refuses an
// output that is the archive.
ExtractReport extractLevel(const std::string& archive_path, const std::string& output,
                           const ExtractOptions& options);

} // namespace ridge
