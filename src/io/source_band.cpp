#include "source_band.h"

#include "georeference.h"
#include "number_format.h"

#include "ridge/core/error.h"
#include "ridge/core/parameter_check.h"

#include <cpl_string.h>
#include <gdal_vrt.h>
#include <ogr_srs_api.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cfloat>
#include <cmath>
#include <numbers>

namespace ridge::io::detail {

namespace {

std::string lowerTrimmed(const std::string& s)
{
    const auto first = s.find_first_not_of(" \t");
    if (first == std::string::npos)
        return {};
    const auto last = s.find_last_not_of(" \t");
    std::string out = s.substr(first, last - first + 1);
    std::transform(out.begin(), out.end(), out.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return out;
}

bool isComplex(GDALDataType type)
{
    return GDALDataTypeIsComplex(type) != 0;
}

// "; it has N subdatasets, e.g. NAME" for container formats (netCDF, HDF, ...) whose rasters
// live in subdatasets, so the user knows what to open instead.
std::string subdatasetHint(GDALDatasetH ds)
{
    char** subdatasets = GDALGetMetadata(ds, "SUBDATASETS");
    const int count = CSLCount(subdatasets) / 2;
    if (count == 0)
        return {};
    const char* first = CSLFetchNameValue(subdatasets, "SUBDATASET_1_NAME");
    return "; it has " + std::to_string(count) + " subdataset" + (count == 1 ? "" : "s") +
           (first ? std::string(", e.g. ") + first : std::string());
}

} // namespace

std::optional<double> verticalUnitFactor(const std::string& unit)
{
    const std::string u = lowerTrimmed(unit);
    if (u.empty() || u == "m" || u == "metre" || u == "meter" || u == "metres" || u == "meters")
        return 1.0;
    if (u == "ft" || u == "foot" || u == "feet" || u == "international foot")
        return 0.3048;
    if (u == "us survey foot" || u == "us-ft" || u == "ftus")
        return 1200.0 / 3937.0;
    return std::nullopt;
}

void validateOptions(const std::string& path, const IngestOptions& options)
{
    try {
        options.validate();
    } catch (const Error& e) {
        throw Error(path + ": " + e.what());
    }
}

namespace {

// z_scale's magnitude is the range's concern; its sign only mirrors the codes.
void checkZScale(const std::string& name, double z_scale)
{
    checkParameter(name, z_scale, ValueRange::any());
    if (!IngestOptions::kZScaleMagnitudeRange.contains(std::abs(z_scale)))
        throw Error(name + " is " + ridge::formatNumber(z_scale) + ": its magnitude must be " +
                    IngestOptions::kZScaleMagnitudeRange.describe());
}

} // namespace

SourceBand::SourceBand(const std::string& path, const IngestOptions& options) : path_(path)
{
    validateOptions(path, options);
    ensureGdalRegistered();
    GdalErrorCapture capture;

    // GTiff decodes blocks on all cores with this option; other drivers would warn about an
    // unknown open option, so it is only passed to GTiff.
    CPLStringList open_options;
    GDALDriverH driver = GDALIdentifyDriverEx(path.c_str(), GDAL_OF_RASTER, nullptr, nullptr);
    if (driver && EQUAL(GDALGetDriverShortName(driver), "GTiff"))
        open_options.SetNameValue("NUM_THREADS", "ALL_CPUS");
    const auto open = [&] {
        dataset_.reset(GDALOpenEx(path.c_str(),
                                  GDAL_OF_RASTER | GDAL_OF_READONLY | GDAL_OF_VERBOSE_ERROR,
                                  nullptr, open_options.List(), nullptr));
        if (!dataset_)
            fail(withGdalDetail("cannot open as a raster", capture));
    };
    open();
    // Threads only help compressed blocks, and GDAL 3.6's threaded reader of an uncompressed
    // multi-band GeoTIFF prints a bogus libtiff error for every block ("Bad value 2 for
    // ExtraSamples tag", from its worker threads, past any capture): read those on one thread.
    if (open_options.Count() > 0 && GDALGetRasterCount(dataset_.get()) > 1 &&
        !GDALGetMetadataItem(dataset_.get(), "COMPRESSION", "IMAGE_STRUCTURE")) {
        open_options.Clear();
        open();
    }

    if (GDALGetRasterCount(dataset_.get()) >= 1)
        appendWrapColumn();

    const int band_count = GDALGetRasterCount(dataset_.get());
    if (band_count < 1)
        fail("has no raster band" + subdatasetHint(dataset_.get()));
    if (options.band > band_count)
        fail("band " + std::to_string(options.band) + " was asked for, but it has " +
             (band_count == 1
                  ? std::string("1 band")
                  : std::to_string(band_count) + " bands (1.." + std::to_string(band_count) + ")"));
    band_number_ = options.band;
    band_ = GDALGetRasterBand(dataset_.get(), band_number_);
    width_ = GDALGetRasterBandXSize(band_);
    height_ = GDALGetRasterBandYSize(band_);
    if (width_ < 2 || height_ < 2)
        fail("raster is " + std::to_string(width_) + "x" + std::to_string(height_) +
             " samples; at least 2x2 are needed (too small)");

    type_ = GDALGetRasterDataType(band_);
    if (type_ == GDT_Unknown || isComplex(type_))
        fail(std::string("data type ") + GDALGetDataTypeName(type_) + " is not supported");
    if (type_ == GDT_Byte) {
        // GDAL < 3.7 has no GDT_Int8; signed bytes are Byte bands flagged like this.
        const char* pixel_type = GDALGetMetadataItem(band_, "PIXELTYPE", "IMAGE_STRUCTURE");
        signed_byte_ = pixel_type && EQUAL(pixel_type, "SIGNEDBYTE");
    }

    GDALGetBlockSize(band_, &block_width_, &block_height_);
    block_width_ = std::clamp(block_width_, 1, width_);
    block_height_ = std::clamp(block_height_, 1, height_);

    const char* unit = GDALGetRasterUnitType(band_);
    vertical_units_ = unit ? unit : "";
    const double unit_factor = verticalUnitFactor(vertical_units_).value_or(1.0);
    int has_scale = 0;
    int has_offset = 0;
    double band_scale = GDALGetRasterScale(band_, &has_scale);
    double band_offset = GDALGetRasterOffset(band_, &has_offset);
    if (!has_scale)
        band_scale = 1.0;
    if (!has_offset)
        band_offset = 0.0;
    z_.scale = options.z_scale ? *options.z_scale : band_scale * unit_factor;
    z_.offset = options.z_offset ? *options.z_offset : band_offset * unit_factor;
    // Given options were validated above; these checks speak to the band's own scale/offset.
    try {
        checkZScale("z_scale", z_.scale);
        checkParameter("z_offset", z_.offset, IngestOptions::kZOffsetRange);
    } catch (const Error& e) {
        fail(std::string(e.what()) + " (from the band's scale " + formatNumber(band_scale) +
             " and offset " + formatNumber(band_offset) + ", unit '" + vertical_units_ + "')");
    }

    // 64-bit integer bands keep their nodata apart (a double cannot hold every value); the
    // samples are compared as doubles after RasterIO's conversion, so convert it alike.
    int has_nodata = 0;
    double nodata = 0;
    if (type_ == GDT_Int64)
        nodata = static_cast<double>(GDALGetRasterNoDataValueAsInt64(band_, &has_nodata));
    else if (type_ == GDT_UInt64)
        nodata = static_cast<double>(GDALGetRasterNoDataValueAsUInt64(band_, &has_nodata));
    else
        nodata = GDALGetRasterNoDataValue(band_, &has_nodata);
    if (has_nodata) {
        // Float32 samples are compared as GDAL compares them: in the band's own precision.
        const bool as_float = type_ == GDT_Float32 && std::abs(nodata) <= FLT_MAX;
        nodata_ = as_float ? static_cast<double>(static_cast<float>(nodata)) : nodata;
    }

    // A real mask (internal/external mask or alpha band) is read alongside the data. Masks
    // that GDAL derives from nodata (GMF_NODATA) or that are all valid add nothing.
    const int flags = GDALGetMaskFlags(band_);
    has_mask_band_ =
        (flags & (GMF_PER_DATASET | GMF_ALPHA)) != 0 && (flags & (GMF_NODATA | GMF_ALL_VALID)) == 0;

    const GeoReference geo = readGeoReference(dataset_.get(), width_, height_, options);
    if (wantsGeoidShift(options.vertical_shift, geo.vertical_datum)) {
        if (!geo.has_geotransform)
            fail("its heights cannot be shifted to the ellipsoid: it has no geotransform "
                 "(--novshift keeps them as they are)");
        geoid_shift_ =
            std::make_unique<GeoidShift>(path_, geo.crs_wkt, geo.vertical_datum, geo.geotransform);
    }
}

SourceBand::~SourceBand() = default;

void SourceBand::describeHeights(GeoReference& geo) const
{
    if (!geoid_shift_)
        return;
    geo.vertical_shift = GeoReference::Shift{geoid_shift_->from(), geoid_shift_->operation()};
    geo.vertical_datum = VerticalDatum{geoid_shift_->target(), std::nullopt,
                                       geoid_shift_->from().describe() + " shifted through " +
                                           geoid_shift_->operation()};
}

void SourceBand::readUndulations(int y0, int rows, std::vector<double>& out) const
{
    out.assign(geoid_shift_ ? static_cast<size_t>(rows) * width_ : 0, 0.0);
    if (geoid_shift_)
        geoid_shift_->undulations(y0, rows, width_, out.data());
}

void SourceBand::appendWrapColumn()
{
    GDALDatasetH ds = dataset_.get();
    const int w = GDALGetRasterXSize(ds), h = GDALGetRasterYSize(ds);
    std::array<double, 6> gt{};
    OGRSpatialReferenceH srs = GDALGetSpatialRef(ds);
    if (!srs || !OSRIsGeographic(srs) || GDALGetGeoTransform(ds, gt.data()) != CE_None)
        return;
    if (gt[2] != 0.0 || gt[4] != 0.0 || !(gt[1] > 0.0) || w < 2)
        return;
    const double degrees = gt[1] * OSRGetAngularUnits(srs, nullptr) * 180.0 / std::numbers::pi;
    const double period = 360.0 / degrees;
    // A whole turn to 5% of a column (ETOPO5 states 0.0833341° for 5'), without the repeated
    // column already (w == period + 1 closes by itself).
    if (std::abs(period - std::round(period)) > 0.05 || w != int64_t(std::round(period)))
        return;
    // A real mask would not follow into the VRT: such rasters keep their open seam.
    for (int b = 1; b <= GDALGetRasterCount(ds); ++b) {
        const int flags = GDALGetMaskFlags(GDALGetRasterBand(ds, b));
        if ((flags & (GMF_PER_DATASET | GMF_ALPHA)) != 0 &&
            (flags & (GMF_NODATA | GMF_ALL_VALID)) == 0)
            return;
    }
    DatasetPtr vrt(VRTCreate(w + 1, h));
    if (!vrt)
        return;
    GDALSetGeoTransform(vrt.get(), gt.data());
    GDALSetSpatialRef(vrt.get(), srs);
    for (int b = 1; b <= GDALGetRasterCount(ds); ++b) {
        GDALRasterBandH src = GDALGetRasterBand(ds, b);
        if (GDALAddBand(vrt.get(), GDALGetRasterDataType(src), nullptr) != CE_None)
            fail("cannot repeat column 0 after the last one (VRT band)");
        GDALRasterBandH dst = GDALGetRasterBand(vrt.get(), b);
        int has = 0;
        const double nodata = GDALGetRasterNoDataValue(src, &has);
        if (has)
            GDALSetRasterNoDataValue(dst, nodata);
        const double scale = GDALGetRasterScale(src, &has);
        if (has)
            GDALSetRasterScale(dst, scale);
        const double offset = GDALGetRasterOffset(src, &has);
        if (has)
            GDALSetRasterOffset(dst, offset);
        if (const char* unit = GDALGetRasterUnitType(src))
            GDALSetRasterUnitType(dst, unit);
        GDALSetDescription(dst, GDALGetDescription(src));
        GDALSetRasterColorInterpretation(dst, GDALGetRasterColorInterpretation(src));
        if (const char* pixel_type = GDALGetMetadataItem(src, "PIXELTYPE", "IMAGE_STRUCTURE"))
            GDALSetMetadataItem(dst, "PIXELTYPE", pixel_type, "IMAGE_STRUCTURE");
        auto* sourced = static_cast<VRTSourcedRasterBandH>(dst);
        if (VRTAddSimpleSource(sourced, src, 0, 0, w, h, 0, 0, w, h, "near", VRT_NODATA_UNSET) !=
                CE_None ||
            VRTAddSimpleSource(sourced, src, 0, 0, 1, h, w, 0, 1, h, "near", VRT_NODATA_UNSET) !=
                CE_None)
            fail("cannot repeat column 0 after the last one (VRT source)");
    }
    wrapped_source_ = std::move(dataset_);
    dataset_ = std::move(vrt);
}

void SourceBand::checkHeightRange(double lo_value, double hi_value, const std::string& what) const
{
    const double a = z_.toMetres(lo_value), b = z_.toMetres(hi_value);
    const double lo = std::min(a, b), hi = std::max(a, b);
    const ValueRange heights = ValueRange::closed(-kMaxAbsHeightMetres, kMaxAbsHeightMetres);
    if (heights.contains(lo) && heights.contains(hi))
        return;
    fail("z_scale " + ridge::formatNumber(z_.scale) + " and z_offset " +
         ridge::formatNumber(z_.offset) + " map " + what + " [" + ridge::formatNumber(lo_value) +
         ", " + ridge::formatNumber(hi_value) + "] to heights [" + ridge::formatNumber(lo) + ", " +
         ridge::formatNumber(hi) + "] m, beyond the ±" + ridge::formatNumber(kMaxAbsHeightMetres) +
         " m any height may reach; check the z-scale (or the band's scale and unit)");
}

void SourceBand::checkSpacing(const GeoReference& geo) const
{
    if (geo.spacing_from_user)
        return; // IngestOptions::validate checked it
    const double spacing[2] = {geo.spacing_x, geo.spacing_y};
    try {
        checkParameters("the ground spacing its georeferencing gives (m)", spacing, 2,
                        IngestOptions::kSpacingRange);
    } catch (const Error& e) {
        fail(e.what());
    }
}

std::vector<std::string> SourceBand::bandNames() const
{
    std::vector<std::string> names;
    const int count = GDALGetRasterCount(dataset_.get());
    for (int b = 1; b <= count; ++b) {
        GDALRasterBandH band = GDALGetRasterBand(dataset_.get(), b);
        const char* description = band ? GDALGetDescription(band) : nullptr;
        const GDALColorInterp interp =
            band ? GDALGetRasterColorInterpretation(band) : GCI_Undefined;
        if (description && *description)
            names.push_back(description);
        else if (interp != GCI_Undefined)
            names.push_back(GDALGetColorInterpretationName(interp));
        else
            names.push_back("band " + std::to_string(b));
    }
    return names;
}

std::string SourceBand::dataTypeName() const
{
    return signed_byte_ ? "Int8" : GDALGetDataTypeName(type_);
}

bool SourceBand::isNodata(double value) const
{
    if (!nodata_)
        return false;
    return value == *nodata_ || (std::isnan(*nodata_) && std::isnan(value));
}

int SourceBand::stripRows(int64_t target_bytes, int sample_bytes) const
{
    const int64_t row_bytes = static_cast<int64_t>(width_) * sample_bytes;
    const int64_t target_rows = std::max<int64_t>(1, target_bytes / row_bytes);
    const int64_t rows = std::max<int64_t>(1, target_rows / block_height_) * block_height_;
    return static_cast<int>(std::min<int64_t>(rows, height_));
}

int64_t SourceBand::blockRowBytes() const
{
    const int64_t blocks_across = (width_ + block_width_ - 1) / block_width_;
    return blocks_across * block_width_ * block_height_ * GDALGetDataTypeSizeBytes(type_);
}

void SourceBand::readRows(int y0, int rows, GDALDataType buffer_type, void* out) const
{
    GdalErrorCapture capture;
    if (GDALRasterIO(band_, GF_Read, 0, y0, width_, rows, out, width_, rows, buffer_type, 0, 0) !=
        CE_None)
        fail(withGdalDetail("cannot read rows " + std::to_string(y0) + ".." +
                                std::to_string(y0 + rows - 1),
                            capture));
}

void SourceBand::readMaskRows(int y0, int rows, uint8_t* out) const
{
    GdalErrorCapture capture;
    if (GDALRasterIO(GDALGetMaskBand(band_), GF_Read, 0, y0, width_, rows, out, width_, rows,
                     GDT_Byte, 0, 0) != CE_None)
        fail(withGdalDetail("cannot read the mask of rows " + std::to_string(y0) + ".." +
                                std::to_string(y0 + rows - 1),
                            capture));
}

void SourceBand::readValues(int y0, int rows, double* out, std::vector<uint8_t>& mask_scratch) const
{
    readRows(y0, rows, GDT_Float64, out);
    const size_t count = static_cast<size_t>(rows) * width_;
    const uint8_t* mask = nullptr;
    if (has_mask_band_) {
        mask_scratch.resize(count);
        readMaskRows(y0, rows, mask_scratch.data());
        mask = mask_scratch.data();
    }
    for (size_t i = 0; i < count; ++i) {
        const double v = out[i];
        if (isNodata(v) || (mask && mask[i] == 0)) {
            out[i] = std::nan("");
        } else if (!std::isfinite(v)) {
            const size_t x = i % width_;
            const size_t y = y0 + i / width_;
            fail("non-finite value " + formatNumber(v) + " at sample (" + std::to_string(x) + ", " +
                 std::to_string(y) + ") (x = column, y = row) is not declared nodata");
        }
    }
}

void SourceBand::fail(const std::string& problem) const
{
    throw Error(path_ + ": " + problem);
}

} // namespace ridge::io::detail

namespace ridge::io {

void IngestOptions::validate() const
{
    if (spacing)
        checkParameter("spacing", *spacing, kSpacingRange);
    if (z_scale)
        detail::checkZScale("z_scale", *z_scale);
    if (z_offset)
        checkParameter("z_offset", *z_offset, kZOffsetRange);
    if (max_error)
        checkParameter("max_error", *max_error, kMaxErrorRange);
    if (sea_level)
        checkParameter("sea_level", *sea_level, kSeaLevelRange);
    checkParameter("band", int64_t{band}, 1, kMaxBand);
    if (vertical_datum)
        resolveVerticalDatum(*vertical_datum); // throws naming vertical_datum
    if (fill_voids != VoidFill::All && fill_voids != VoidFill::Interior &&
        fill_voids != VoidFill::None)
        throw Error("fill_voids is " + std::to_string(static_cast<int>(fill_voids)) +
                    ": must be all, interior or none");
}

const char* voidFillName(VoidFill mode)
{
    switch (mode) {
    case VoidFill::All:
        return "all";
    case VoidFill::Interior:
        return "interior";
    case VoidFill::None:
        return "none";
    }
    return "invalid";
}

VoidFill parseVoidFill(const std::string& name)
{
    for (VoidFill mode : {VoidFill::All, VoidFill::Interior, VoidFill::None})
        if (name == voidFillName(mode))
            return mode;
    throw Error("fill_voids is '" + name + "': must be all, interior or none");
}

} // namespace ridge::io
