// GeoTIFF and PNG output through GDAL, written to a temporary file and renamed into place.
// GDAL only takes names: it is given AtomicOutput::temporaryPath(), "/proc/self/fd/N", which
// reopens the AtomicOutput's own (usually unnamed) file and cannot be redirected by a
// planted symlink. Both drivers write through it (tests/io/output_safety_io_test.cpp).
#include "ridge/io/raster_writer.h"

#include "gdal_support.h"

#include "ridge/core/atomic_output.h"
#include "ridge/core/error.h"

#include <cpl_string.h>

namespace ridge::io {

namespace {

using detail::DatasetPtr;
using detail::GdalErrorCapture;
using detail::withGdalDetail;

[[noreturn]] void fail(const std::string& path, const std::string& problem,
                       const GdalErrorCapture& capture)
{
    throw Error(path + ": " + withGdalDetail(problem, capture));
}

GDALDriverH driver(const std::string& path, const char* name)
{
    detail::ensureGdalRegistered();
    GDALDriverH d = GDALGetDriverByName(name);
    if (!d)
        throw Error(path + ": GDAL's " + name + " driver is not available");
    return d;
}

void checkSize(const std::string& path, int width, int height)
{
    if (width < 1 || height < 1)
        throw Error(path + ": cannot write a " + std::to_string(width) + "x" +
                    std::to_string(height) + " raster");
}

// Closes `ds` and fails if GDAL reported any error while writing or closing it (GDAL 3.6's
// GDALClose returns nothing, so the error handler is the only witness).
void closeChecked(DatasetPtr& ds, const std::string& path, const GdalErrorCapture& capture)
{
    ds.reset();
    if (capture.hasFailure())
        fail(path, "cannot write", capture);
}

} // namespace

void writeGeoTiff(const std::string& path, const float* metres, int width, int height,
                  const GeoReference& geo, std::optional<double> nodata)
{
    checkSize(path, width, height);
    GDALDriverH gtiff = driver(path, "GTiff");
    AtomicOutput output(path);
    GdalErrorCapture capture;
    // Everything goes into the TIFF itself; a side-car .aux.xml would not follow the rename
    // (and "/proc/self/fd/N.aux.xml" cannot be created anyway).
    detail::ScopedThreadConfig no_pam("GDAL_PAM_ENABLED", "NO");

    CPLStringList options;
    options.SetNameValue("TILED", "YES");
    options.SetNameValue("COMPRESS", "DEFLATE");
    options.SetNameValue("PREDICTOR", "3"); // floating-point predictor
    options.SetNameValue("BIGTIFF", "IF_SAFER");
    DatasetPtr ds(GDALCreate(gtiff, output.temporaryPath().c_str(), width, height, 1,
                             GDT_Float32, options.List()));
    if (!ds)
        fail(path, "cannot create GeoTIFF", capture);
    if (geo.has_geotransform) {
        std::array<double, 6> gt = geo.geotransform;
        if (GDALSetGeoTransform(ds.get(), gt.data()) != CE_None)
            fail(path, "cannot set the geotransform", capture);
    }
    if (!geo.crs_wkt.empty() && GDALSetProjection(ds.get(), geo.crs_wkt.c_str()) != CE_None)
        fail(path, "cannot set the coordinate reference system", capture);
    GDALRasterBandH band = GDALGetRasterBand(ds.get(), 1);
    GDALSetRasterUnitType(band, "m");
    if (nodata && GDALSetRasterNoDataValue(band, *nodata) != CE_None)
        fail(path, "cannot set the nodata value", capture);
    if (GDALRasterIO(band, GF_Write, 0, 0, width, height, const_cast<float*>(metres), width,
                     height, GDT_Float32, 0, 0) != CE_None)
        fail(path, "cannot write samples", capture);
    closeChecked(ds, path, capture);
    output.commit();
}

void writePng(const std::string& path, const uint8_t* pixels, int width, int height, int channels)
{
    checkSize(path, width, height);
    if (channels != 1 && channels != 3 && channels != 4)
        throw Error(path + ": cannot write a PNG with " + std::to_string(channels) +
                    " channels (1, 3 or 4)");
    GDALDriverH png = driver(path, "PNG");
    AtomicOutput output(path);
    GdalErrorCapture capture;
    // The PNG driver stores what PNG cannot hold in a side-car TEMPORARY.aux.xml, which would
    // not follow the rename; there is nothing worth keeping in it.
    detail::ScopedThreadConfig no_pam("GDAL_PAM_ENABLED", "NO");

    // PNG has no Create(), only CreateCopy() from a dataset: wrap the pixels without a copy.
    // The MEM dataset is only read from, so casting away const is safe.
    DatasetPtr source = detail::wrapInMemDataset(const_cast<uint8_t*>(pixels), GDT_Byte, width,
                                                 height, channels);
    if (channels == 4)
        GDALSetRasterColorInterpretation(GDALGetRasterBand(source.get(), 4), GCI_AlphaBand);
    DatasetPtr ds(GDALCreateCopy(png, output.temporaryPath().c_str(), source.get(), FALSE,
                                 nullptr, nullptr, nullptr));
    if (!ds)
        fail(path, "cannot write PNG", capture);
    closeChecked(ds, path, capture);
    output.commit();
}

} // namespace ridge::io
