// GeoTIFF and PNG output through GDAL, written to a temporary file and renamed into place.
// GDAL only takes names: it is given AtomicOutput::temporaryPath(), "/proc/self/fd/N", which
// reopens the AtomicOutput's own (usually unnamed) file and cannot be redirected by a
// planted symlink. Both drivers write through it (tests/io/output_safety_io_test.cpp).
#include "ridge/io/raster_writer.h"

#include "gdal_support.h"

#include "ridge/core/atomic_output.h"
#include "ridge/core/error.h"
#include "ridge/core/file_identity.h"
#include "ridge/core/file_io.h"
#include "ridge/core/nearest_name.h"

#include <cpl_string.h>
#include <cpl_vsi.h>

#include <atomic>
#include <cerrno>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <memory>
#include <unistd.h>

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

// Every message GDAL emits on this thread, warnings included, while alive: creation-option
// validation speaks only in warnings.
class GdalMessageCapture {
  public:
    GdalMessageCapture() { CPLPushErrorHandlerEx(&GdalMessageCapture::handle, this); }
    ~GdalMessageCapture() { CPLPopErrorHandler(); }
    GdalMessageCapture(const GdalMessageCapture&) = delete;
    GdalMessageCapture& operator=(const GdalMessageCapture&) = delete;
    std::string joined() const
    {
        std::string text;
        for (const std::string& m : messages_)
            text += (text.empty() ? "" : "; ") + m;
        return text;
    }

  private:
    static void CPL_STDCALL handle(CPLErr error_class, CPLErrorNum, const char* message)
    {
        if (error_class == CE_Debug)
            return;
        auto* self = static_cast<GdalMessageCapture*>(CPLGetErrorHandlerUserData());
        if (!self || self->messages_.size() >= 8)
            return;
        try {
            self->messages_.emplace_back(message ? message : "");
        } catch (...) {
            // An exception must not unwind through GDAL's C frames.
        }
    }
    std::vector<std::string> messages_;
};

struct SampleTypeRange {
    const char* name;
    bool integer;
    double lo, hi;
};

// GDAL 3.6's real types (Int8 arrived in 3.7; 64-bit integers are left out: heights are
// 16-bit codes, and a double cannot check their range exactly).
constexpr SampleTypeRange kSampleTypes[] = {
    {"Byte", true, 0, 255},
    {"UInt16", true, 0, 65535},
    {"Int16", true, -32768, 32767},
    {"UInt32", true, 0, 4294967295.0},
    {"Int32", true, -2147483648.0, 2147483647.0},
    {"Float32", false, -FLT_MAX, FLT_MAX},
    {"Float64", false, -DBL_MAX, DBL_MAX},
};

bool isYes(const char* value)
{
    return value && CPLTestBool(value);
}

// Raster drivers that can write (Create or CreateCopy) through /vsimem/, MEM and VRT excluded:
// their "files" hold nothing (MEM) or only point at the in-memory source (VRT).
bool writableThroughVsi(GDALDriverH d)
{
    const std::string name = GDALGetDriverShortName(d);
    return name != "MEM" && name != "VRT" &&
           isYes(GDALGetMetadataItem(d, GDAL_DCAP_RASTER, nullptr)) &&
           (isYes(GDALGetMetadataItem(d, GDAL_DCAP_CREATE, nullptr)) ||
            isYes(GDALGetMetadataItem(d, GDAL_DCAP_CREATECOPY, nullptr))) &&
           isYes(GDALGetMetadataItem(d, GDAL_DCAP_VIRTUALIO, nullptr));
}

std::vector<std::string> writableDriverNames()
{
    detail::ensureGdalRegistered();
    std::vector<std::string> names;
    for (int i = 0; i < GDALGetDriverCount(); ++i)
        if (writableThroughVsi(GDALGetDriver(i)))
            names.emplace_back(GDALGetDriverShortName(GDALGetDriver(i)));
    return names;
}

GDALDriverH writableDriver(const std::string& name)
{
    detail::ensureGdalRegistered();
    GDALDriverH d = name.empty() ? nullptr : GDALGetDriverByName(name.c_str());
    if (!d) {
        const std::optional<std::string> nearest = nearestName(name, writableDriverNames());
        throw Error("output_format '" + name + "': no such GDAL driver" +
                    (nearest ? "; did you mean '" + *nearest + "'?" : "") +
                    " (gdalinfo --formats lists them; those marked 'w' write)");
    }
    if (!writableThroughVsi(d))
        throw Error("output_format '" + name + "': GDAL's " + name +
                    " driver cannot write a raster file through GDAL's virtual files "
                    "(ridge writes there first so that no half-written output is left)");
    return d;
}

// The creation options: GTiff's defaults unless given, then the caller's.
CPLStringList creationOptions(GDALDriverH d, const RasterFormat& format, const SampleType& type)
{
    CPLStringList options;
    for (const std::string& option : format.creation_options) {
        const size_t eq = option.find('=');
        if (eq == std::string::npos || eq == 0)
            throw Error("creation_options '" + option + "': expected NAME=VALUE");
        options.SetNameValue(option.substr(0, eq).c_str(), option.substr(eq + 1).c_str());
    }
    if (std::string(GDALGetDriverShortName(d)) == "GTiff") {
        const auto fallback = [&options](const char* key, const char* value) {
            if (!options.FetchNameValue(key))
                options.SetNameValue(key, value);
        };
        fallback("TILED", "YES");
        fallback("COMPRESS", "DEFLATE");
        // 3: floating-point predictor; 2: horizontal differencing, the one for integers.
        fallback("PREDICTOR", type.integer ? "2" : "3");
        fallback("BIGTIFF", "IF_SAFER");
    }
    return options;
}

std::string quoted(const std::vector<std::string>& names)
{
    std::string text;
    for (const std::string& n : names)
        text += (text.empty() ? "" : ", ") + n;
    return text;
}

// Removes a /vsimem/ directory and everything in it when the write is over, however it ends.
struct VsiMemDirectory {
    std::string path;
    ~VsiMemDirectory() { VSIRmdirRecursive(path.c_str()); }
};

} // namespace

bool SampleType::holdsExactly(double value) const
{
    if (!std::isfinite(value) || value < lo || value > hi)
        return false;
    if (integer)
        return std::floor(value) == value;
    if (name == "Float32")
        return double(float(value)) == value;
    return true;
}

SampleType sampleType(const std::string& name)
{
    std::vector<std::string> names;
    for (const SampleTypeRange& t : kSampleTypes) {
        if (EQUAL(name.c_str(), t.name))
            return {t.name, t.integer, t.lo, t.hi};
        names.emplace_back(t.name);
    }
    const std::optional<std::string> nearest = nearestName(name, names);
    throw Error("output_type '" + name + "': not a type ridge writes" +
                (nearest ? "; did you mean '" + *nearest + "'?" : "") + " (" + quoted(names) + ")");
}

void checkRasterFormat(const RasterFormat& format, const SampleType& type)
{
    GDALDriverH d = writableDriver(format.output_format);
    const CPLStringList options = creationOptions(d, format, type);
    {
        GdalMessageCapture capture;
        if (!GDALValidateCreationOptions(d, options.List()))
            throw Error("creation_options: GDAL's " + format.output_format +
                        " driver refuses them: " + capture.joined());
    }
    // NaN is the nodata of floating-point types (GDAL's "-a_nodata nan").
    const bool nan_for_float =
        format.nodata_value && std::isnan(*format.nodata_value) && !type.integer;
    if (format.nodata_value && !nan_for_float && !type.holdsExactly(*format.nodata_value))
        throw Error("nodata_value " + std::to_string(*format.nodata_value) + ": " + type.name +
                    " cannot hold it (" + (type.integer ? "an integer in [" : "a number in [") +
                    std::to_string(type.lo) + ", " + std::to_string(type.hi) + "])");
}

void writeRaster(const std::string& path, const std::vector<double>& values, int width, int height,
                 const SampleType& type, const GeoReference& geo, const RasterFormat& format,
                 const std::vector<std::string>& inputs)
{
    checkSize(path, width, height);
    if (values.size() != size_t(width) * size_t(height))
        throw Error(path + ": " + std::to_string(values.size()) + " values for a " +
                    std::to_string(width) + "x" + std::to_string(height) + " raster");
    checkRasterFormat(format, type);
    refuseOutputOverInput(path, inputs);
    GDALDriverH d = writableDriver(format.output_format);
    const CPLStringList options = creationOptions(d, format, type);
    const GDALDataType gdal_type = GDALGetDataTypeByName(type.name.c_str());

    GdalErrorCapture capture;
    // The source: a MEM band of the output type (GDAL converts the doubles, which the type
    // holds, exactly), with the georeference, the unit and the nodata value.
    DatasetPtr source(
        GDALCreate(GDALGetDriverByName("MEM"), "", width, height, 1, gdal_type, nullptr));
    if (!source)
        fail(path, "cannot allocate the raster", capture);
    if (geo.has_geotransform) {
        std::array<double, 6> gt = geo.geotransform;
        if (GDALSetGeoTransform(source.get(), gt.data()) != CE_None)
            fail(path, "cannot set the geotransform", capture);
    }
    if (!geo.crs_wkt.empty() && GDALSetProjection(source.get(), geo.crs_wkt.c_str()) != CE_None)
        fail(path, "cannot set the coordinate reference system", capture);
    GDALRasterBandH band = GDALGetRasterBand(source.get(), 1);
    GDALSetRasterUnitType(band, "m");
    if (format.nodata_value && GDALSetRasterNoDataValue(band, *format.nodata_value) != CE_None)
        fail(path, "cannot set the nodata value", capture);
    if (GDALRasterIO(band, GF_Write, 0, 0, width, height, const_cast<double*>(values.data()), width,
                     height, GDT_Float64, 0, 0) != CE_None)
        fail(path, "cannot hold the samples", capture);

    // The driver writes into a private /vsimem/ directory; its files are then published.
    static std::atomic<uint64_t> serial{0};
    const VsiMemDirectory scratch{"/vsimem/ridge-write-" + std::to_string(::getpid()) + "-" +
                                  std::to_string(serial++)};
    VSIMkdir(scratch.path.c_str(), 0700);
    const std::filesystem::path final_path(path);
    const std::string name = final_path.filename().string();
    {
        DatasetPtr ds(GDALCreateCopy(d, (scratch.path + "/" + name).c_str(), source.get(), TRUE,
                                     options.List(), nullptr, nullptr));
        if (!ds)
            fail(path, "GDAL's " + format.output_format + " driver cannot write it", capture);
        closeChecked(ds, path, capture);
    }
    const CPLStringList made(VSIReadDir(scratch.path.c_str()));
    std::vector<std::string> files; // the main file last
    for (int i = 0; i < made.size(); ++i)
        if (std::string(made[i]) != name)
            files.emplace_back(made[i]);
    files.push_back(name);
    std::vector<std::unique_ptr<AtomicOutput>> outputs;
    for (const std::string& file : files) {
        const std::string target = (final_path.parent_path() / file).string();
        if (file != name)
            refuseOutputOverInput(target, inputs);
        vsi_l_offset size = 0;
        const GByte* data = VSIGetMemFileBuffer((scratch.path + "/" + file).c_str(), &size, FALSE);
        if (!data && file == name)
            throw Error(path + ": GDAL's " + format.output_format + " driver wrote no file");
        outputs.push_back(std::make_unique<AtomicOutput>(target));
        if (data)
            writeAll(outputs.back()->fd(), data, size_t(size), target);
    }
    for (const std::unique_ptr<AtomicOutput>& output : outputs)
        output->commit();
}

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
    DatasetPtr ds(GDALCreate(gtiff, output.temporaryPath().c_str(), width, height, 1, GDT_Float32,
                             options.List()));
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
    if (GDALRasterIO(band, GF_Write, 0, 0, width, height, const_cast<float*>(metres), width, height,
                     GDT_Float32, 0, 0) != CE_None)
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
    DatasetPtr source =
        detail::wrapInMemDataset(const_cast<uint8_t*>(pixels), GDT_Byte, width, height, channels);
    if (channels == 4)
        GDALSetRasterColorInterpretation(GDALGetRasterBand(source.get(), 4), GCI_AlphaBand);
    DatasetPtr ds(GDALCreateCopy(png, output.temporaryPath().c_str(), source.get(), FALSE, nullptr,
                                 nullptr, nullptr));
    if (!ds)
        fail(path, "cannot write PNG", capture);
    closeChecked(ds, path, capture);
    output.commit();
}

} // namespace ridge::io
