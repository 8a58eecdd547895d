#pragma once
// Writing rasters through GDAL. Outputs are atomic (ridge::AtomicOutput): a failed write
// leaves nothing at `path`.
#include "ridge/io/raster_source.h"

#include <cstdint>
#include <optional>
#include <string>

namespace ridge::io {

// Writes a single-band Float32 GeoTIFF (DEFLATE, tiled) of `metres` (row-major width x
// height). `geotransform`/`crs_wkt` are written when has_geotransform / non-empty, and the
// band's nodata value when `nodata` is set (NaN allowed).
void writeGeoTiff(const std::string& path, const float* metres, int width, int height,
                  const GeoReference& geo, std::optional<double> nodata = std::nullopt);

// Writes an 8-bit PNG with `channels` = 1 (grey), 3 (RGB) or 4 (RGBA), pixels row-major
// interleaved.
void writePng(const std::string& path, const uint8_t* pixels, int width, int height,
              int channels);

} // namespace ridge::io
