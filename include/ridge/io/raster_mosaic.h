#pragma once
// Rasters as parts of a whole, for builds split into shards (pipeline/shard.h): several
// inputs joined into one mosaic (gdalbuildvrt's VRT), where each input lies in it, and a
// pixel window of a raster opened as a dataset of its own.
#include <string>
#include <vector>

namespace ridge::io {

// A pixel rectangle of a raster: columns [x, x + width), rows [y, y + height).
struct PixelWindow {
    int x = 0;
    int y = 0;
    int width = 0;
    int height = 0;
    bool intersects(const PixelWindow& o) const
    {
        return x < o.x + o.width && o.x < x + width && y < o.y + o.height && o.y < y + height;
    }
    bool operator==(const PixelWindow&) const = default;
};

struct MosaicPart {
    std::string path;
    PixelWindow footprint; // where the input's pixels lie in the mosaic (clamped to it)
};

// Joins `inputs` (one band each read, any GDAL raster) into a VRT written at `vrt_path`
// (GDALBuildVRT with gdalbuildvrt's defaults: one CRS, the inputs' average resolution; where
// inputs overlap, the later one wins). Written under a temporary name and renamed, so
// nothing half-written is left. Throws ridge::Error naming the input or output.
void buildMosaic(const std::vector<std::string>& inputs, const std::string& vrt_path);

// Where each of `inputs` lies in raster `mosaic` (from their geotransforms); an input that is
// the mosaic itself, or without a geotransform, covers it all. Throws ridge::Error naming the
// file when one cannot be opened.
std::vector<MosaicPart> mosaicParts(const std::string& mosaic,
                                    const std::vector<std::string>& inputs);

// Window `window` of raster `path` as a dataset of its own (a VRT in GDAL's memory file
// system), which every reader takes like a file; removed when destroyed. Its samples are the
// raster's, exactly; its band, type, nodata, scale/offset and CRS are the raster's.
class RasterWindow {
  public:
    RasterWindow(const std::string& path, const PixelWindow& window);
    ~RasterWindow();
    RasterWindow(const RasterWindow&) = delete;
    RasterWindow& operator=(const RasterWindow&) = delete;
    const std::string& path() const { return vsimem_path_; }

  private:
    std::string vsimem_path_;
};

} // namespace ridge::io
