#pragma once
// A layer of water on the elevation raster's grid (`ridge build --water FILE`): lakes,
// reservoirs, rivers, a coastline — whatever the heights cannot tell apart from land (a lake
// at 1,200 m, land below sea level). Internal to ridge_io.
#include "ridge/io/raster_source.h"

#include "gdal_support.h"

#include <cstdint>
#include <string>
#include <vector>

namespace ridge::io::detail {

class WaterLayer {
  public:
    // Opens `path`: any raster GDAL reads (band 1; a sample is water where it is data and not
    // 0) or any vector dataset OGR reads (every layer; a sample is water where its centre lies
    // inside a polygon, or on a line or point, GDALRasterize's default rule). It is resampled
    // (nearest) or burnt onto the grid `grid` of `width` × `height` samples, reprojected to
    // the grid's CRS when both state one (GDALWarp, GDALRasterize). An elevation raster
    // without a geotransform takes only a raster of its own size, read sample for sample.
    // Throws Error naming `path` when it cannot be opened, holds neither raster nor vector
    // data, or cannot be placed on the grid.
    WaterLayer(const std::string& path, const GeoReference& grid, int width, int height);

    // Sets out[k] = 1 where sample k of rows [y0, y0 + rows) is water, 0 elsewhere
    // (out[rows · width]). Throws Error naming the layer when GDAL fails.
    void readRows(int y0, int rows, uint8_t* out);

    const std::string& path() const { return path_; }

  private:
    void warpRows(int y0, int rows, uint8_t* out);
    void burnRows(int y0, int rows, uint8_t* out);
    std::array<double, 6> stripGeotransform(int y0) const;
    [[noreturn]] void fail(const std::string& problem, const GdalErrorCapture& capture) const;

    std::string path_;
    GeoReference grid_;
    int width_ = 0;
    DatasetPtr source_;                    // as opened
    DatasetPtr band_one_;                  // rasters: a VRT of band 1 (GDALWarp warps every band)
    std::vector<std::string> layer_names_; // vectors
    std::vector<float> values_;            // a warped strip
};

} // namespace ridge::io::detail
