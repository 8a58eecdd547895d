#pragma once
// The metadata document of a .ridge archive (docs/FORMAT.md, "Metadata"), parsed once when
// the archive is opened: every documented key with its type checked, the values that repeat
// header fields cross-checked against the header, numbers finite. Consumers (extract, verify,
// info) read these fields instead of re-parsing the JSON with silent fallbacks.
//
// Unknown keys are ignored (forward compatibility); the document as stored stays available
// as ArchiveReader::metadataJson() for tools that print it whole.
#include "ridge/archive/format.h"

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace ridge::archive {

// "source": the raster the archive was built from, as ingest saw it.
struct SourceMetadata {
    std::string path;          // the source as named at build (an absolute path: its file name)
    std::string data_type;     // GDAL data type name of the band read, e.g. "Int16"
    std::optional<int> band;   // that band, 1-based (absent before 2027: band 1)
    int64_t width = 0;         // == header width
    int64_t height = 0;        // == header height
    int64_t valid_samples = 0; // >= 0 (streamed builds over-count: see docs/FORMAT.md)
    int64_t voids_filled = 0;  // in [0, width·height]
    int64_t voids_kept = 0;    // kept as nodata; in [0, width·height − voids_filled]
    std::string fill_voids = "all"; // "all", "interior", "none" (version 1: "all", implied)
    std::string void_fill;          // how voids were filled (free text)
    std::optional<double> nodata;   // the source band's declared nodata value (finite), if any
    double min_metres = 0.0;        // over the valid samples; finite, <= max_metres
    double max_metres = 0.0;
    bool exact = false; // every valid sample is its code's height (quantization_error 0)
};

// "georeference.vertical_datum": what the heights are measured from.
struct VerticalDatumMetadata {
    std::string name;        // non-empty, e.g. "EGM96 height"
    std::optional<int> epsg; // of the vertical CRS, in [1, 2^31 - 1]
    std::string origin;      // "source CRS" or "--vertical-datum" (free text)
};

// "georeference": where the finest grid sits (GDAL conventions, pixel-is-area).
struct GeoreferenceMetadata {
    std::string crs_wkt;        // may be empty
    bool geographic = false;    // CRS is lon/lat
    std::string vertical_units; // as the source states them, may be empty
    bool spacing_from_user = false;
    std::optional<std::array<double, 6>> geotransform;   // GDAL order, finite, of the finest grid
    std::optional<VerticalDatumMetadata> vertical_datum; // absent: unknown
};

// "build.vertical_shift": the source's heights were above a geoid and were shifted to the
// ellipsoid at build (io::VerticalShift); verify --source shifts the source alike.
struct VerticalShiftMetadata {
    std::string from;      // the source's vertical CRS ("EGM96 height"), non-empty
    int from_epsg = 0;     // its EPSG code, in [1, 2^31 - 1]
    std::string operation; // PROJ's name of the transformation (free text)
};

// "build": the options the archive was built with.
struct BuildMetadata {
    int patch_size = 0;   // == header patch_size
    int block_cells = 0;  // == header block_cells
    std::string codec;    // a codec name whose id is header codec_id ("progressive-paper" → 2)
    std::string filter;   // filterName of header filter_id
    double z_scale = 1.0; // source value → metres: value · z_scale + z_offset; finite, non-zero
    double z_offset = 0.0;
    std::optional<double> max_error;          // metres, finite >= 0 (ingest's --max-error)
    std::optional<double> codec_max_error;    // metres, finite >= 0 (lossy codecs' --max-error)
    std::optional<std::string> codec_variant; // free text (progressive codecs)
    std::optional<std::string> block_errors;  // free text: stored or derived
    std::optional<VerticalShiftMetadata> vertical_shift; // absent: heights as the source's
};

// "water" (version 4): how the build decided the water flags (pyramid/sample_flags.h).
struct WaterMetadata {
    // Valid samples at or below this height (metres, finite) are water; none: the height
    // rule was off (`build --sea-level none`).
    std::optional<double> sea_level = 0.0;
    // The water layer given to `build --water`, as given (a file name, never read back).
    std::optional<std::string> layer;
    int64_t samples = 0; // finest samples flagged water, in [0, width·height]
};

struct ArchiveMetadata {
    SourceMetadata source;
    GeoreferenceMetadata georeference;
    BuildMetadata build;
    // Version 4. Before: absent (sea_level 0, no layer, samples 0 — water was decided from
    // the decoded heights, ArchiveReader::storesSampleFlags).
    WaterMetadata water;
    std::string generator;
};

// Bounds on the document (docs/FORMAT.md, "Metadata"), checked before it is parsed: what
// ridge writes is a few KB (the CRS WKT dominates) and three levels deep, and every consumer
// (messages, `info --json`) then handles any document in bounded time, memory and stack.
inline constexpr uint32_t kMaxMetadataBytes = 16u << 20;
inline constexpr int kMaxMetadataDepth =
    32; // containers around a value, the document's own included

// Parses and checks `json` against `header` (already checked itself). Throws ridge::Error
// "metadata: WHAT" naming the key: "metadata: not JSON (...)", "metadata: source.width is
// missing", "metadata: build.z_scale is \"1\": must be a number", "metadata:
// build.patch_size is 65 but the header says 129", "metadata: values nested more than 32
// deep", "metadata: not JSON: a NUL byte at offset 812 ...". A georeference.geotransform must
// be invertible with finite corners (what query, info and extract need of it).
ArchiveMetadata parseArchiveMetadata(std::string_view json, const Header& header);

} // namespace ridge::archive
