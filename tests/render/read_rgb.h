#pragma once
// A PNG (or any GDAL raster with three or more bands) read back as RGB bytes, row-major:
// what the render tests compare pictures with.
#include <gdal_priv.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace ridge::test {

// Empty when the file cannot be read or has fewer than three bands.
inline std::vector<uint8_t> readRgb(const std::string& path, int& width, int& height)
{
    GDALAllRegister();
    std::unique_ptr<GDALDataset> ds(
        GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
    if (!ds || ds->GetRasterCount() < 3)
        return {};
    width = ds->GetRasterXSize();
    height = ds->GetRasterYSize();
    std::vector<uint8_t> rgb(size_t(width) * height * 3);
    int bands[3] = {1, 2, 3};
    if (ds->RasterIO(GF_Read, 0, 0, width, height, rgb.data(), width, height, GDT_Byte, 3, bands, 3,
                     3 * width, 1, nullptr) != CE_None)
        return {};
    return rgb;
}

} // namespace ridge::test
