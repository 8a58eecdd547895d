#pragma once
// The heights' band of a source raster (IngestOptions::band, default 1) as both ingestRaster
// and ReferenceRaster see it: opened and
// validated, with one definition of "void", one z_scale/z_offset rule and one strip reader.
#include "gdal_support.h"
#include "geoid_shift.h"

#include "ridge/io/raster_source.h"

#include <cstdint>
#include <string>
#include <vector>

namespace ridge::io::detail {

// metres = value * scale + offset.
struct ZTransform {
    double scale = 1.0;
    double offset = 0.0;

    double toMetres(double value) const { return value * scale + offset; }
};

// Metres per unit of a band's vertical unit type ("ft", "US survey foot", "m", ...).
// Unknown units are taken as metres (nullopt tells the caller it did not recognise them).
std::optional<double> verticalUnitFactor(const std::string& unit);

// Rejects invalid IngestOptions with an Error naming `path`.
void validateOptions(const std::string& path, const IngestOptions& options);

class SourceBand {
  public:
    // Opens band options.band read-only. Throws Error("path: ...") when the file cannot be
    // opened, has no raster band or not that one, is smaller than 2x2, or has an unsupported
    // data type.
    SourceBand(const std::string& path, const IngestOptions& options);
    ~SourceBand();
    SourceBand(SourceBand&&) = default;

    const std::string& path() const { return path_; }
    // Whether the source's columns span 360° of longitude and column 0 was appended after its
    // last column, so that the grid closes around the Earth (width() counts it).
    bool wrapsAround() const { return wrapped_source_ != nullptr; }
    GDALDatasetH dataset() const { return dataset_.get(); }
    GDALRasterBandH band() const { return band_; }
    int bandNumber() const { return band_number_; } // 1-based
    // Each band's name: description, else colour interpretation, else "band N".
    std::vector<std::string> bandNames() const;
    int width() const { return width_; }
    int height() const { return height_; }
    GDALDataType dataType() const { return type_; }
    bool isSignedByte() const { return signed_byte_; }
    std::string dataTypeName() const;
    const ZTransform& z() const { return z_; }
    const std::string& verticalUnits() const { return vertical_units_; }

    // Nodata as declared by the band (nullopt when none). A NaN nodata marks NaN samples.
    const std::optional<double>& nodata() const { return nodata_; }
    // The dataset has a real mask (per-dataset mask or alpha band), read alongside the data.
    bool hasMaskBand() const { return has_mask_band_; }
    bool isNodata(double value) const;

    // Rows per strip: a multiple of the band's block height holding about `target_bytes` of
    // samples of `sample_bytes` each (at least one block row, at most the raster).
    int stripRows(int64_t target_bytes, int sample_bytes) const;
    // Bytes of one row of blocks in GDAL's block cache.
    int64_t blockRowBytes() const;

    // Reads rows [y0, y0 + rows) of the band converted to `buffer_type` into `out`.
    void readRows(int y0, int rows, GDALDataType buffer_type, void* out) const;
    // Reads the mask band's rows [y0, y0 + rows) (0 = void). Only when hasMaskBand().
    void readMaskRows(int y0, int rows, uint8_t* out) const;

    // Reads rows [y0, y0 + rows) as stored values (before z_scale/z_offset) with voids as
    // NaN. Throws Error with the sample position for a non-finite value that is not a void.
    // `mask_scratch` is reused between calls to hold the mask strip.
    void readValues(int y0, int rows, double* out, std::vector<uint8_t>& mask_scratch) const;

    // Heights above a geoid become heights above the ellipsoid (IngestOptions::vertical_shift):
    // the shift, or null when the heights stay as the source gives them.
    const GeoidShift* geoidShift() const { return geoid_shift_.get(); }
    // N (metres) at rows [y0, y0 + rows) into out[rows * width()]: heights in metres plus N
    // are above the ellipsoid. Empty when there is no shift.
    void readUndulations(int y0, int rows, std::vector<double>& out) const;
    // Records a shift in `geo` (vertical_shift set, vertical_datum the ellipsoid).
    void describeHeights(GeoReference& geo) const;

    // Throws Error naming the file, z_scale, z_offset and both ranges unless z() maps stored
    // values [lo_value, hi_value] to heights within ±kMaxAbsHeightMetres. `what` says what
    // the values are ("the Int16 type's values", "its values").
    void checkHeightRange(double lo_value, double hi_value, const std::string& what) const;
    // Throws Error naming the file unless a spacing taken from the georeferencing is within
    // IngestOptions::kSpacingRange (user spacings are validated with the options).
    void checkSpacing(const GeoReference& geo) const;

    // Throws Error("path: problem[: GDAL's messages]").
    [[noreturn]] void fail(const std::string& problem) const;

  private:
    // The wrap (wrapsAround): run once the dataset is open, before its bands are read.
    void appendWrapColumn();

    std::string path_;
    // A raster that goes round the Earth is read through a VRT (dataset_) with column 0
    // repeated after its last column; the source stays open under it (closed after it).
    DatasetPtr wrapped_source_;
    DatasetPtr dataset_;
    GDALRasterBandH band_ = nullptr;
    int band_number_ = 1;
    int width_ = 0;
    int height_ = 0;
    int block_width_ = 1;
    int block_height_ = 1;
    GDALDataType type_ = GDT_Unknown;
    bool signed_byte_ = false;
    ZTransform z_;
    std::string vertical_units_;
    std::optional<double> nodata_;
    bool has_mask_band_ = false;
    std::unique_ptr<GeoidShift> geoid_shift_;
};

} // namespace ridge::io::detail
