// WaterLayer: a water raster or vector layer placed on the elevation grid strip by strip, so
// that a build that streams its source never holds a whole-grid mask.
#include "water_layer.h"

#include "ridge/core/error.h"

#include <gdal_utils.h>
#include <ogr_api.h>

#include <algorithm>
#include <cmath>

namespace ridge::io::detail {

namespace {

// GDAL's utility option lists are argv-like: a null-terminated array of C strings.
class Arguments {
  public:
    Arguments(std::initializer_list<std::string> args) : strings_(args) {}
    void add(std::string s) { strings_.push_back(std::move(s)); }
    char** argv()
    {
        pointers_.clear();
        for (std::string& s : strings_)
            pointers_.push_back(s.data());
        pointers_.push_back(nullptr);
        return pointers_.data();
    }

  private:
    std::vector<std::string> strings_;
    std::vector<char*> pointers_;
};

} // namespace

WaterLayer::WaterLayer(const std::string& path, const GeoReference& grid, int width, int height)
    : path_(path), grid_(grid), width_(width)
{
    GdalErrorCapture capture;
    ensureGdalRegistered();
    source_.reset(GDALOpenEx(path.c_str(), GDAL_OF_RASTER | GDAL_OF_VECTOR | GDAL_OF_READONLY,
                             nullptr, nullptr, nullptr));
    if (!source_)
        fail("cannot open the water layer", capture);
    GDALDatasetH ds = source_.get();
    if (GDALGetRasterCount(ds) > 0) {
        const bool georeferenced = [&] {
            double gt[6];
            return GDALGetGeoTransform(ds, gt) == CE_None;
        }();
        if (!grid.has_geotransform || !georeferenced) {
            if (GDALGetRasterXSize(ds) != width || GDALGetRasterYSize(ds) != height)
                fail("a water raster without georeferencing (or for an elevation raster "
                     "without one) must have the elevation raster's size, " +
                         std::to_string(width) + " x " + std::to_string(height) + "; it has " +
                         std::to_string(GDALGetRasterXSize(ds)) + " x " +
                         std::to_string(GDALGetRasterYSize(ds)),
                     capture);
            return; // read sample for sample
        }
        Arguments args{"-of", "VRT", "-b", "1"};
        GDALTranslateOptions* options = GDALTranslateOptionsNew(args.argv(), nullptr);
        band_one_.reset(GDALTranslate("", ds, options, nullptr));
        GDALTranslateOptionsFree(options);
        if (!band_one_)
            fail("cannot select band 1 of the water raster", capture);
        return;
    }
    for (int k = 0; k < GDALDatasetGetLayerCount(ds); ++k)
        layer_names_.push_back(OGR_L_GetName(GDALDatasetGetLayer(ds, k)));
    if (layer_names_.empty())
        fail("the water layer has neither a raster band nor a vector layer", capture);
    if (!grid.has_geotransform)
        fail("a vector water layer needs a georeferenced elevation raster (it has no "
             "geotransform)",
             capture);
}

std::array<double, 6> WaterLayer::stripGeotransform(int y0) const
{
    std::array<double, 6> gt = grid_.geotransform;
    gt[0] += y0 * gt[2];
    gt[3] += y0 * gt[5];
    return gt;
}

void WaterLayer::readRows(int y0, int rows, uint8_t* out)
{
    const size_t count = static_cast<size_t>(rows) * static_cast<size_t>(width_);
    std::fill(out, out + count, uint8_t{0});
    if (!layer_names_.empty())
        burnRows(y0, rows, out);
    else
        warpRows(y0, rows, out);
}

void WaterLayer::warpRows(int y0, int rows, uint8_t* out)
{
    GdalErrorCapture capture;
    const size_t count = static_cast<size_t>(rows) * static_cast<size_t>(width_);
    values_.assign(count, 0.f);
    if (!band_one_) { // same grid: band 1 as it is, its mask telling data from nodata
        GDALRasterBandH band = GDALGetRasterBand(source_.get(), 1);
        std::vector<uint8_t> mask(count);
        if (GDALRasterIO(band, GF_Read, 0, y0, width_, rows, values_.data(), width_, rows,
                         GDT_Float32, 0, 0) != CE_None ||
            GDALRasterIO(GDALGetMaskBand(band), GF_Read, 0, y0, width_, rows, mask.data(), width_,
                         rows, GDT_Byte, 0, 0) != CE_None)
            fail("cannot read rows " + std::to_string(y0) + ".." + std::to_string(y0 + rows - 1),
                 capture);
        for (size_t k = 0; k < count; ++k)
            out[k] = mask[k] != 0 && std::isfinite(values_[k]) && values_[k] != 0.f;
        return;
    }
    // Nearest resampling onto a strip of the grid; samples the layer does not cover, or where
    // it is nodata, keep the initial 0 (not water).
    const DatasetPtr strip = wrapInMemDataset(values_.data(), GDT_Float32, width_, rows);
    std::array<double, 6> gt = stripGeotransform(y0);
    GDALSetGeoTransform(strip.get(), gt.data());
    if (!grid_.crs_wkt.empty())
        GDALSetProjection(strip.get(), grid_.crs_wkt.c_str());
    Arguments args{"-r", "near", "-q"};
    GDALWarpAppOptions* options = GDALWarpAppOptionsNew(args.argv(), nullptr);
    GDALDatasetH sources[1] = {band_one_.get()};
    int usage_error = 0;
    GDALDatasetH result = GDALWarp(nullptr, strip.get(), 1, sources, options, &usage_error);
    GDALWarpAppOptionsFree(options);
    if (!result || capture.hasFailure())
        fail("cannot resample the water raster onto the elevation grid", capture);
    for (size_t k = 0; k < count; ++k)
        out[k] = std::isfinite(values_[k]) && values_[k] != 0.f;
}

void WaterLayer::burnRows(int y0, int rows, uint8_t* out)
{
    GdalErrorCapture capture;
    const DatasetPtr strip = wrapInMemDataset(out, GDT_Byte, width_, rows);
    std::array<double, 6> gt = stripGeotransform(y0);
    GDALSetGeoTransform(strip.get(), gt.data());
    if (!grid_.crs_wkt.empty())
        GDALSetProjection(strip.get(), grid_.crs_wkt.c_str());
    Arguments args{"-burn", "1", "-q"};
    for (const std::string& name : layer_names_) {
        args.add("-l");
        args.add(name);
    }
    GDALRasterizeOptions* options = GDALRasterizeOptionsNew(args.argv(), nullptr);
    int usage_error = 0;
    GDALDatasetH result = GDALRasterize(nullptr, strip.get(), source_.get(), options, &usage_error);
    GDALRasterizeOptionsFree(options);
    if (!result || capture.hasFailure())
        fail("cannot burn the water layer onto the elevation grid", capture);
}

void WaterLayer::fail(const std::string& problem, const GdalErrorCapture& capture) const
{
    throw Error(path_ + ": " + withGdalDetail(problem, capture));
}

} // namespace ridge::io::detail
