#pragma once
// Helpers for the io tests: make small rasters with GDAL at run time and read files back
// through GDAL independently of ridge::io.
#include <gdal.h>
#include <ogr_srs_api.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace ridge::test {

// Band 1 of a raster as GDAL reads it.
struct GdalBand {
    int width = 0;
    int height = 0;
    std::vector<double> values; // row-major
    std::optional<double> nodata;
    bool has_geotransform = false;
    std::array<double, 6> geotransform{};
    std::string unit;
    std::string wkt;

    double at(int x, int y) const { return values[static_cast<size_t>(y) * width + x]; }
    bool isNodata(size_t i) const
    {
        return nodata && (values[i] == *nodata || (std::isnan(*nodata) && std::isnan(values[i])));
    }
};

inline GdalBand readWithGdal(const std::string& path)
{
    GDALAllRegister();
    GDALDatasetH ds =
        GDALOpenEx(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY, nullptr, nullptr, nullptr);
    if (!ds)
        throw std::runtime_error("test: cannot open " + path);
    GdalBand out;
    GDALRasterBandH band = GDALGetRasterBand(ds, 1);
    out.width = GDALGetRasterXSize(ds);
    out.height = GDALGetRasterYSize(ds);
    out.values.resize(static_cast<size_t>(out.width) * out.height);
    if (GDALRasterIO(band, GF_Read, 0, 0, out.width, out.height, out.values.data(), out.width,
                     out.height, GDT_Float64, 0, 0) != CE_None) {
        GDALClose(ds);
        throw std::runtime_error("test: cannot read " + path);
    }
    int has_nodata = 0;
    const double nodata = GDALGetRasterNoDataValue(band, &has_nodata);
    if (has_nodata)
        out.nodata = nodata;
    out.has_geotransform = GDALGetGeoTransform(ds, out.geotransform.data()) == CE_None;
    const char* unit = GDALGetRasterUnitType(band);
    out.unit = unit ? unit : "";
    const char* wkt = GDALGetProjectionRef(ds);
    out.wkt = wkt ? wkt : "";
    GDALClose(ds);
    return out;
}

// What a test raster gets before it is copied to its driver.
struct RasterSetup {
    std::optional<double> nodata;
    std::string unit;
    std::optional<double> scale;
    std::optional<double> offset;
    std::optional<std::array<double, 6>> geotransform;
    int epsg = 0;
    // Extra work on the MEM dataset (masks, ...), before the copy.
    std::function<void(GDALDatasetH)> customize;
    std::vector<std::string> creation_options;
};

// Writes `values` (row-major, width x height) as band 1 of a `type` raster at `path` with
// `driver` (through a MEM dataset and CreateCopy, so that PNG works too).
inline void writeTestRaster(const std::string& path, const char* driver, GDALDataType type,
                            int width, int height, const std::vector<double>& values,
                            const RasterSetup& setup = {})
{
    GDALAllRegister();
    GDALDatasetH mem = GDALCreate(GDALGetDriverByName("MEM"), "", width, height, 1, type, nullptr);
    GDALRasterBandH band = GDALGetRasterBand(mem, 1);
    if (GDALRasterIO(band, GF_Write, 0, 0, width, height, const_cast<double*>(values.data()), width,
                     height, GDT_Float64, 0, 0) != CE_None)
        throw std::runtime_error("test: cannot fill MEM raster");
    if (setup.nodata)
        GDALSetRasterNoDataValue(band, *setup.nodata);
    if (!setup.unit.empty())
        GDALSetRasterUnitType(band, setup.unit.c_str());
    if (setup.scale)
        GDALSetRasterScale(band, *setup.scale);
    if (setup.offset)
        GDALSetRasterOffset(band, *setup.offset);
    if (setup.geotransform) {
        std::array<double, 6> gt = *setup.geotransform;
        GDALSetGeoTransform(mem, gt.data());
    }
    if (setup.epsg) {
        OGRSpatialReferenceH srs = OSRNewSpatialReference(nullptr);
        OSRImportFromEPSG(srs, setup.epsg);
        GDALSetSpatialRef(mem, srs);
        OSRDestroySpatialReference(srs);
    }
    if (setup.customize)
        setup.customize(mem);
    std::vector<const char*> options;
    for (const std::string& o : setup.creation_options)
        options.push_back(o.c_str());
    options.push_back(nullptr);
    GDALDatasetH out = GDALCreateCopy(GDALGetDriverByName(driver), path.c_str(), mem, FALSE,
                                      const_cast<char**>(options.data()), nullptr, nullptr);
    GDALClose(mem);
    if (!out)
        throw std::runtime_error("test: cannot write " + path);
    GDALClose(out);
}

inline int openDatasetCount()
{
    GDALDatasetH* list = nullptr;
    int count = 0;
    GDALGetOpenDatasets(&list, &count);
    return count;
}

} // namespace ridge::test
