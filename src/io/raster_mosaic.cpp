// Mosaics and windows through GDAL's utilities (gdal_utils.h: GDALBuildVRT, GDALTranslate),
// the library behind gdalbuildvrt and gdal_translate, not a hand-written VRT.
#include "ridge/io/raster_mosaic.h"

#include "gdal_support.h"

#include "ridge/core/error.h"

#include <cpl_string.h>
#include <cpl_vsi.h>
#include <gdal_utils.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <unistd.h>

namespace ridge::io {

namespace {

detail::DatasetPtr openRaster(const std::string& path, const detail::GdalErrorCapture& capture)
{
    detail::DatasetPtr ds(
        GDALOpenEx(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY, nullptr, nullptr, nullptr));
    if (!ds)
        throw Error(detail::withGdalDetail(path + ": cannot open as a raster", capture));
    return ds;
}

} // namespace

void buildMosaic(const std::vector<std::string>& inputs, const std::string& vrt_path)
{
    if (inputs.empty())
        throw Error(vrt_path + ": a mosaic needs at least one input");
    detail::ensureGdalRegistered();
    const detail::GdalErrorCapture capture;
    std::vector<const char*> names;
    for (const std::string& input : inputs) {
        openRaster(input, capture); // names the input that does not open
        names.push_back(input.c_str());
    }
    const std::string temporary = vrt_path + ".tmp" + std::to_string(::getpid()) + ".vrt";
    CPLStringList argv;
    argv.AddString("-q");
    GDALBuildVRTOptions* options = GDALBuildVRTOptionsNew(argv.List(), nullptr);
    int usage_error = FALSE;
    GDALDatasetH vrt = GDALBuildVRT(temporary.c_str(), int(names.size()), nullptr, names.data(),
                                    options, &usage_error);
    GDALBuildVRTOptionsFree(options);
    if (vrt)
        GDALClose(vrt); // writes the VRT; a failure is reported through CPLError
    if (!vrt || capture.hasFailure()) {
        std::error_code ignored;
        std::filesystem::remove(temporary, ignored);
        throw Error(detail::withGdalDetail(vrt_path + ": cannot build the mosaic VRT", capture));
    }
    std::error_code error;
    std::filesystem::rename(temporary, vrt_path, error);
    if (error) {
        std::filesystem::remove(temporary, error);
        throw Error(vrt_path + ": cannot write: " + error.message());
    }
}

std::vector<MosaicPart> mosaicParts(const std::string& mosaic,
                                    const std::vector<std::string>& inputs)
{
    detail::ensureGdalRegistered();
    const detail::GdalErrorCapture capture;
    const detail::DatasetPtr whole = openRaster(mosaic, capture);
    const int width = GDALGetRasterXSize(whole.get()), height = GDALGetRasterYSize(whole.get());
    const PixelWindow all{0, 0, width, height};
    double m[6];
    const bool mosaic_placed = GDALGetGeoTransform(whole.get(), m) == CE_None && m[1] != 0 &&
                               m[5] != 0 && m[2] == 0 && m[4] == 0;
    std::vector<MosaicPart> parts;
    for (const std::string& input : inputs) {
        const detail::DatasetPtr ds = openRaster(input, capture);
        double g[6];
        if (!mosaic_placed || GDALGetGeoTransform(ds.get(), g) != CE_None || g[2] != 0 ||
            g[4] != 0) {
            parts.push_back({input, all});
            continue;
        }
        // The input's corners in mosaic pixels, widened to whole pixels.
        const double x0 = (g[0] - m[0]) / m[1], y0 = (g[3] - m[3]) / m[5];
        const double x1 = (g[0] + g[1] * GDALGetRasterXSize(ds.get()) - m[0]) / m[1];
        const double y1 = (g[3] + g[5] * GDALGetRasterYSize(ds.get()) - m[3]) / m[5];
        auto lo = [](double a, double b, int limit) {
            return std::clamp(int(std::floor(std::min(a, b) + 1e-6)), 0, limit);
        };
        auto hi = [](double a, double b, int limit) {
            return std::clamp(int(std::ceil(std::max(a, b) - 1e-6)), 0, limit);
        };
        const int px0 = lo(x0, x1, width), px1 = hi(x0, x1, width);
        const int py0 = lo(y0, y1, height), py1 = hi(y0, y1, height);
        parts.push_back({input, {px0, py0, px1 - px0, py1 - py0}});
    }
    return parts;
}

RasterWindow::RasterWindow(const std::string& path, const PixelWindow& window)
{
    static std::atomic<uint64_t> serial{0};
    detail::ensureGdalRegistered();
    const detail::GdalErrorCapture capture;
    const detail::DatasetPtr source = openRaster(path, capture);
    const int width = GDALGetRasterXSize(source.get()), height = GDALGetRasterYSize(source.get());
    if (window.width < 1 || window.height < 1 || window.x < 0 || window.y < 0 ||
        window.x > width - window.width || window.y > height - window.height)
        throw Error(path + ": window " + std::to_string(window.x) + "," + std::to_string(window.y) +
                    " " + std::to_string(window.width) + "x" + std::to_string(window.height) +
                    " is outside its " + std::to_string(width) + "x" + std::to_string(height) +
                    " pixels");
    vsimem_path_ = "/vsimem/ridge_window_" + std::to_string(::getpid()) + "_" +
                   std::to_string(serial++) + ".vrt";
    CPLStringList argv;
    for (const char* arg : {"-of", "VRT", "-srcwin"})
        argv.AddString(arg);
    for (int v : {window.x, window.y, window.width, window.height})
        argv.AddString(std::to_string(v).c_str());
    GDALTranslateOptions* options = GDALTranslateOptionsNew(argv.List(), nullptr);
    int usage_error = FALSE;
    GDALDatasetH out = GDALTranslate(vsimem_path_.c_str(), source.get(), options, &usage_error);
    GDALTranslateOptionsFree(options);
    if (out)
        GDALClose(out);
    if (!out || capture.hasFailure()) {
        VSIUnlink(vsimem_path_.c_str());
        throw Error(detail::withGdalDetail(path + ": cannot open a window of it", capture));
    }
}

RasterWindow::~RasterWindow()
{
    VSIUnlink(vsimem_path_.c_str());
}

} // namespace ridge::io
