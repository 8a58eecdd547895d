#pragma once
// Ingest of elevation rasters through GDAL (one band, by default the first, of anything GDAL
// can read).
//
// This is the only module (with raster_writer.h) that talks to GDAL; GDAL headers never
// appear in ridge's public headers.
#include "ridge/core/height_grid.h"
#include "ridge/core/parameter_check.h"
#include "ridge/core/progress.h"
#include "ridge/io/crs_summary.h"

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace ridge::io {

// Where the raster sits on Earth. Pixel-is-area convention as GDAL reports it.
struct GeoReference {
    bool has_geotransform = false;
    std::array<double, 6> geotransform{0, 1, 0, 0, 0, -1}; // GDAL order
    std::string crs_wkt;                                   // empty when the source has no CRS
    bool geographic = false;                               // CRS is lon/lat (degrees)
    std::string vertical_units; // as the source states them ("m", "ft", ...), may be empty
    // Ground sample spacing in metres. Geographic CRS: along the parallel and the meridian at
    // the centre latitude, on the CRS's ellipsoid. Projected: geotransform * linear units.
    // No georeferencing: IngestOptions::spacing (default 1) and spacing_from_user = true.
    double spacing_x = 1.0;
    double spacing_y = 1.0;
    bool spacing_from_user = false;
    // What the heights are measured from: IngestOptions::vertical_datum when given, else the
    // vertical part of the source's CRS (compound CRSs), else unknown. After a vertical
    // shift: the ellipsoid ("WGS 84 ellipsoidal height", origin "vertical shift").
    VerticalDatum vertical_datum;
    // Set when the heights were shifted from a geoid to the ellipsoid (VerticalShift).
    struct Shift {
        VerticalDatum from;    // the source's datum (always with an EPSG code)
        std::string operation; // PROJ's name of the transformation
    };
    std::optional<Shift> vertical_shift;
};

// Which nodata samples become terrain (`ridge build --fill-voids`).
//  All:      every void is filled from its valid neighbours (ridge before December 2026).
//  Interior: voids enclosed by data (SRTM holes) are filled; nodata 8-connected to the
//            raster border (the empty collar of a reprojected DEM, sea, a clipping mask)
//            stays nodata: it is not terrain, only outside the survey.
//  None:     every void stays nodata.
// Kept nodata still gets filled codes (so the pyramid, codecs and bounds run unchanged) and
// is recorded in ElevationRaster::nodata, and per patch in the archive.
enum class VoidFill { All, Interior, None };
const char* voidFillName(VoidFill mode); // "all", "interior", "none"
// Throws ridge::Error("fill_voids is 'X': must be all, interior or none").
VoidFill parseVoidFill(const std::string& name);

// Whether heights above a geoid become heights above the ellipsoid (`ridge build --vshift`,
// `--novshift`, after gdalwarp's options): h = H + N through PROJ's transformation and grid
// (src/io/geoid_shift.h).
//  Auto:      when the heights' vertical datum (IngestOptions::vertical_datum, else the
//             source's compound CRS) is a registered vertical CRS (EGM96 height, EPSG:5773).
//  Ellipsoid: always; a source whose datum is unknown or unregistered is an error.
//  None:      never; heights stay as the source gives them.
enum class VerticalShift { Auto, Ellipsoid, None };

// How a band that is not 8/16-bit integers becomes 16-bit codes, settled over the whole
// raster (CodeRowReader::codeMapping): what a reader of part of it — a sharded build's window
// — must be given to make the codes the whole raster's reader makes.
struct CodeMapping {
    bool exact = false;          // integers spanning ≤ 65536 values: code = |value − origin|
    double integer_origin = 0.0; // the value of code 0 (exact mappings)
    int64_t max_code = 65535;    // 65534 when the raster has voids (the top code stays free)
    HeightQuantization quantization; // scale, offset; max_error measured over the whole raster
};

struct IngestOptions {
    // The ranges validate() enforces. Spacings and max_error are positive and no larger than
    // anything real (ridge/core/height_grid.h); z_offset is a height. The magnitude of z_scale
    // starts at a nanometre per stored unit: below, code steps underflow the archive's float
    // fields. The heights z_scale and z_offset make must also lie within ±kMaxAbsHeightMetres,
    // which only the raster's values can tell (checked when it is opened).
    static constexpr ValueRange kSpacingRange = ValueRange::openClosed(0.0, kMaxSpacingMetres);
    static constexpr ValueRange kZScaleMagnitudeRange = {1e-9, ValueRange::any().hi, false, false};
    static constexpr ValueRange kZOffsetRange =
        ValueRange::closed(-kMaxAbsHeightMetres, kMaxAbsHeightMetres);
    static constexpr ValueRange kMaxErrorRange = ValueRange::openClosed(0.0, kMaxAbsHeightMetres);
    // Band numbers start at 1 (GDAL's); GDAL datasets hold at most 65536 bands per file.
    static constexpr int64_t kMaxBand = 65536;

    // The band that holds the heights (gdal_translate's -b), 1-based. Opening a raster with
    // fewer bands is an error naming both numbers.
    int band = 1;
    // The heights' vertical datum (`build --vertical-datum`): an EPSG code of a vertical CRS
    // or a name (resolveVerticalDatum). Replaces what the source's CRS says; unset: the
    // source's CRS's vertical part, if any.
    std::optional<std::string> vertical_datum;
    VerticalShift vertical_shift = VerticalShift::Auto;

    // Ground spacing (metres) for rasters without georeferencing. Ignored when the raster
    // is georeferenced, unless force_spacing is set.
    std::optional<double> spacing;
    bool force_spacing = false;
    // metres = stored value * z_scale + z_offset. When unset, derived from the band's own
    // scale/offset and unit type (feet -> metres); when set, they replace that.
    std::optional<double> z_scale;
    std::optional<double> z_offset;
    // Largest allowed quantization error (metres) for input that is not exactly
    // representable in 16 bits. Unset: the finest step that fits 16 bits.
    std::optional<double> max_error;
    VoidFill fill_voids = VoidFill::Interior;
    // Water (pyramid/sample_flags.h): valid samples whose source height is at or below
    // `sea_level` metres (after z_scale/z_offset) are water; nullopt turns the rule off (land
    // below sea level: Death Valley, the Dead Sea shore, polders). `water_layer`, when not
    // empty, is a raster or vector file of water (any GDAL raster: data other than 0; any
    // OGR vector: its features) added to the rule: lakes, reservoirs, rivers.
    static constexpr ValueRange kSeaLevelRange =
        ValueRange::closed(-kMaxAbsHeightMetres, kMaxAbsHeightMetres);
    std::optional<double> sea_level = 0.0;
    std::string water_layer;
    // CodeRowReader only, for bands that are not 8/16-bit integers: this mapping instead of a
    // survey and an error pass over the raster; a value it does not hold within its max_error
    // is an error naming the file (the raster changed since the mapping was made).
    std::optional<CodeMapping> code_mapping;
    Progress progress;

    // Throws ridge::Error("NAME is VALUE: must be RANGE") for the first set option outside
    // its range above (NaN and infinities included, sea_level too), for a band outside
    // [1, kMaxBand], a vertical_datum resolveVerticalDatum refuses, and a fill_voids that is
    // not one of the enumerators.
    void validate() const;
};

struct IngestStats {
    std::string data_type;     // GDAL data type name of the band read, e.g. "Int16"
    int64_t valid_samples = 0; // samples that were not nodata
    int64_t voids_filled = 0;  // nodata samples filled from valid neighbours
    int64_t voids_kept = 0;    // nodata samples kept as nodata (IngestOptions::fill_voids)
    VoidFill fill_voids = VoidFill::Interior; // the mode that decided between the two
    std::optional<double> nodata; // the band's declared nodata value (source units), if any
    double min_metres = 0.0;      // over valid samples, after z_scale/z_offset
    double max_metres = 0.0;
    bool exact = false;   // every valid sample is represented exactly by its code
    double z_scale = 1.0; // effective metres = value * z_scale + z_offset
    double z_offset = 0.0;
    int64_t water_samples =
        0; // valid samples flagged water (IngestOptions::sea_level, water_layer)
};

// The finest grid of the pyramid: codes + their metric meaning + where it came from.
struct ElevationRaster {
    std::string source_path;
    CodeGrid grid;
    HeightQuantization quantization;
    GeoReference geo;
    IngestStats stats;
    // 1 where a finest sample is kept as nodata (its code is filled all the same), 0 where it
    // is data; empty when every sample is data (stats.voids_kept == 0).
    std::vector<uint8_t> nodata;
    // The sample flags of each finest sample (pyramid/sample_flags.h: kSampleWater,
    // kSampleFilled); 0 on kept nodata. Empty when no sample has a flag.
    std::vector<uint8_t> flags;
};

// Reads band options.band of `path` into 16-bit codes, fills voids, records georeferencing.
//
// Quantization: 8/16-bit integer bands are exact (code = value - type minimum). Other types
// get a pre-pass for min/max; if every valid value is an integer and the range fits 16 bits
// the result is exact, otherwise step = 2 * max_error (or range / 65535 when unset) and
// quantization.max_error is the measured worst error.
// Voids (declared nodata, NaN when nodata is NaN, or GDAL's mask band where the dataset
// has a real mask) are filled by GDALFillNodata (inverse-distance weighting from the void's
// valid border, then smoothing passes) and rounded to codes; those options.fill_voids keeps
// as nodata are filled too and marked in ElevationRaster::nodata, the others flagged
// kSampleFilled. Water is flagged from the source's values (options.sea_level; a filled
// sample by its filled code) and options.water_layer.
//
// Throws ridge::Error naming `path` and the problem for: unreadable / unrecognised file,
// no raster band, grid smaller than 2x2, all samples nodata, non-finite values that are not
// declared nodata (with the first sample position), a range that cannot meet max_error in
// 16 bits, options outside their ranges (IngestOptions::validate), a z_scale / z_offset
// (given or the band's own) that maps the band's values beyond ±kMaxAbsHeightMetres (8/16-bit
// integers: the type's whole range, whose codes the archive can hold; other types: the
// values present), a georeferenced spacing beyond kMaxSpacingMetres.
// Memory: 2 bytes per sample plus a strip buffer; voids add 1 byte per sample while filling.
ElevationRaster ingestRaster(const std::string& path, const IngestOptions& options = {});

// What sizing a build needs to know about a raster before reading any sample: opens
// options.band and reads no pixels (cheap even for a 10^6 x 10^6 VRT), so it can come before
// CodeRowReader's pre-pass over non-integer data. Same errors as opening for ingest
// (options, unreadable file, no such band, < 2x2, unsupported type); the value checks come
// later.
struct RasterProbe {
    int width = 0;
    int height = 0;
    std::string data_type;     // as IngestStats::data_type
    bool direct_codes = false; // 8/16-bit integers: codes read in place, no pre-pass
    bool has_mask_band = false;
    bool declares_nodata = false;
    // Bytes per sample that a strip reader holds besides the codes (values as doubles for
    // non-direct types, the mask strip), and the GDAL block cache it keeps (ingest and
    // CodeRowReader both bound it; a row of blocks must fit twice).
    int strip_extra_bytes_per_sample = 0;
    int64_t block_cache_bytes = 0;
    // Every band of the dataset, in order: its description, else its colour interpretation
    // ("Red", "Gray"), else "band N". More than one: the caller should say which it reads.
    std::vector<std::string> band_names;
};
RasterProbe probeRaster(const std::string& path, const IngestOptions& options = {});

// Strip-wise access to options.band as codes, for builds that never hold the whole grid.
//
// The constructor opens the band and settles the quantization exactly as ingestRaster does
// (8/16-bit integers: exact, no pass over the data; other types: the strip-wise pre-pass for
// range and integrality). Rows can then be read in any order; stats() covers the rows read so
// far, each once however often it was read. Voids cannot be filled strip by strip: readRows
// reports how many it met, and callers fall back to ingestRaster when there are any. Same
// errors as ingestRaster.
class CodeRowReader {
  public:
    CodeRowReader(const std::string& path, const IngestOptions& options);
    ~CodeRowReader();
    CodeRowReader(const CodeRowReader&) = delete;
    CodeRowReader& operator=(const CodeRowReader&) = delete;

    int width() const;
    int height() const;
    const HeightQuantization& quantization() const;
    const GeoReference& geo() const;
    // The mapping of a band that is not 8/16-bit integers (nullopt for those: their codes are
    // the stored values, whatever part of the raster is read).
    std::optional<CodeMapping> codeMapping() const;

    // Reads rows [y0, y0 + rows) into out[rows * width()] as codes and returns the number of
    // void samples among them (their codes are unspecified). `flags`, when given
    // (rows * width() bytes), receives each sample's flags (kSampleWater by the options'
    // sea level and water layer; 0 on voids; nothing is filled here).
    int64_t readRows(int y0, int rows, uint16_t* out, uint8_t* flags = nullptr);
    // Whether any flag can be set (a sea level or a water layer was given).
    bool flagsWater() const;

    // data_type, valid_samples, min/max metres (over the valid samples read so far), exact,
    // z_scale/z_offset, water_samples (rows read with flags, each once); voids_filled is
    // always 0 (this reader fills nothing).
    IngestStats stats() const;

  private:
    struct Impl;
    Impl* impl_ = nullptr;
};

// Strip-wise reader of a source raster's exact values in metres, for verification: no
// quantization, no void filling; voids are reported as NaN. Uses the same z_scale/z_offset
// rules as ingestRaster.
class ReferenceRaster {
  public:
    ReferenceRaster(const std::string& path, const IngestOptions& options);
    ~ReferenceRaster();
    ReferenceRaster(const ReferenceRaster&) = delete;
    ReferenceRaster& operator=(const ReferenceRaster&) = delete;

    int width() const { return width_; }
    int height() const { return height_; }
    // Reads rows [y0, y0 + rows) into out[rows * width()], metres, voids as NaN; shifted to
    // the ellipsoid under options.vertical_shift as the build was. `source_heights`, when
    // given, receives the heights before that shift (what the water rule judges).
    void readRows(int y0, int rows, double* out, double* source_heights = nullptr);

  private:
    struct Impl;
    Impl* impl_ = nullptr;
    int width_ = 0;
    int height_ = 0;
};

} // namespace ridge::io
