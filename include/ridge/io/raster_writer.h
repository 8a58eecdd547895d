#pragma once
// Writing rasters through GDAL. Outputs are atomic (ridge::AtomicOutput): a failed write
// leaves nothing at `path`.
#include "ridge/io/raster_source.h"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace ridge::io {

// Writes a single-band Float32 GeoTIFF (DEFLATE, tiled) of `metres` (row-major width x
// height). `geotransform`/`crs_wkt` are written when has_geotransform / non-empty, and the
// band's nodata value when `nodata` is set (NaN allowed).
void writeGeoTiff(const std::string& path, const float* metres, int width, int height,
                  const GeoReference& geo, std::optional<double> nodata = std::nullopt);

// A GDAL sample type an output can be written in ("Byte", "Int16", "UInt16", "Int32",
// "UInt32", "Float32", "Float64"; names as GDAL spells them, any case), with the values it
// holds: integers in [lo, hi], or any number in [lo, hi] for the floating-point types.
struct SampleType {
    std::string name; // GDAL's spelling
    bool integer = false;
    double lo = 0, hi = 0;

    // Whether `value` is stored exactly (integers: integral and in range; Float32: the nearest
    // float is the value; Float64: any finite value).
    bool holdsExactly(double value) const;
};

// The type named `name`. Throws Error("output_type 'X': ...") naming the known types (and the
// nearest one) for anything else, complex types included.
SampleType sampleType(const std::string& name);

// How writeRaster writes: a GDAL driver that can Create or CreateCopy (short name, "GTiff",
// "PNG", "COG", "AAIGrid", ...), its creation options, and the nodata value of the band.
struct RasterFormat {
    std::string output_format = "GTiff";
    std::vector<std::string> creation_options; // "NAME=VALUE", passed to the driver
    std::optional<double> nodata_value;
};

// Throws Error naming the parameter when `format` cannot be written in `type`: an unknown
// driver (with the nearest writable one), a driver that cannot write rasters or write through
// GDAL's virtual files (which the atomic output needs), a creation option that is not
// NAME=VALUE or that GDAL's validation refuses for the driver, or a nodata value the type does
// not hold. Cheap: for commands to check before their work.
void checkRasterFormat(const RasterFormat& format, const SampleType& type);

// Writes one band of `type` from `values` (row-major width x height; each must already be
// held by the type: the caller rounds) with `geo`'s geotransform and CRS, the unit "m", and
// format.nodata_value when set. GTiff gets TILED=YES, COMPRESS=DEFLATE, a predictor for the
// type and BIGTIFF=IF_SAFER unless the creation options say otherwise.
//
// Every file the driver makes (side-cars such as .aux.xml, .wld or .hdr included) appears
// next to `path` only when all are complete, each through ridge::AtomicOutput, the main file
// last; none may be one of `inputs` (refuseOutputOverInput). The driver writes into GDAL's
// memory files first, so the output is held in memory once more while it is written.
void writeRaster(const std::string& path, const std::vector<double>& values, int width, int height,
                 const SampleType& type, const GeoReference& geo, const RasterFormat& format,
                 const std::vector<std::string>& inputs);

// Writes an 8-bit PNG with `channels` = 1 (grey), 3 (RGB) or 4 (RGBA), pixels row-major
// interleaved.
void writePng(const std::string& path, const uint8_t* pixels, int width, int height, int channels);

} // namespace ridge::io
