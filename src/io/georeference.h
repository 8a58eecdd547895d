#pragma once
#include "ridge/io/raster_source.h"

#include <gdal.h>

namespace ridge::io::detail {

// Geotransform, CRS and ground sample spacing of `dataset` (width x height samples);
// spacing falls back to options.spacing (default 1 m) when the raster is not georeferenced
// or options.force_spacing is set.
GeoReference readGeoReference(GDALDatasetH dataset, int width, int height,
                              const IngestOptions& options);

} // namespace ridge::io::detail
