#pragma once
// `ridge info`: what an archive holds.
#include "ridge/archive/archive_metadata.h"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace ridge {

struct LevelInfo {
    int level = 0;
    int64_t step = 1;          // finest samples between level samples
    int width = 0, height = 0; // level samples inside the valid extent
    int patches_x = 0, patches_y = 0;
    uint64_t bytes = 0;   // blob bytes (block errors + payloads)
    double max_err = 0.0; // largest Err(P), metres
    double max_err_appr = 0.0;
    double level_bound = 0.0; // δ_l, metres
};

// A corner (or the centre) of the raster as gdalinfo lists them: pixel/line (0, 0), (0, H),
// (W, 0), (W, H), (W/2, H/2), in the archive CRS and in WGS 84 longitude/latitude.
struct CornerInfo {
    std::string name; // "Upper Left", "Lower Left", "Upper Right", "Lower Right", "Center"
    double pixel = 0, line = 0;         // GDAL pixel/line
    double x = 0, y = 0;                // archive CRS (geotransform)
    bool has_lon_lat = false;           // false without a CRS or where PROJ cannot convert
    double longitude = 0, latitude = 0; // WGS 84, degrees
};

// Where an archive's bytes go (`ridge info --bytes`): the regions of docs/FORMAT.md, and each
// level's blobs by part. They add up to the file's size.
struct ByteAccount {
    uint64_t header = 0, index = 0, metadata = 0, codec_tables = 0;
    struct Level {
        uint64_t block_errors = 0, validity = 0, sample_flags = 0, payload = 0;
    };
    std::vector<Level> levels;
    uint64_t total() const;
};

struct ArchiveInfo {
    std::string path;
    uint32_t format_version = 0;
    uint64_t file_bytes = 0;
    int width = 0, height = 0, patch_size = 0, level_count = 0;
    int block_cells = 0, block_levels = 0;
    int64_t patch_count = 0;
    std::string codec, filter;
    double height_scale = 1.0, height_offset = 0.0, quantization_error = 0.0;
    double spacing_x = 1.0, spacing_y = 1.0;
    double min_height = 0.0, max_height = 0.0;
    std::string metadata_json;         // the archive's metadata document as stored (valid JSON)
    archive::ArchiveMetadata metadata; // its fields, checked against the header
    std::vector<LevelInfo> levels;
    std::vector<CornerInfo> corners; // empty without a geotransform
    std::string lon_lat_note;        // why corners have no lon/lat (no CRS, PROJ error), or empty

    // The source band as gdalinfo describes it.
    int band = 1;                 // source.band (1 for archives that predate it)
    std::string data_type;        // GDAL type name ("Int16", "Float32")
    std::optional<double> nodata; // the band's declared nodata value, if finite
    // The heights' code step in metres (height_scale) and whether every valid sample is held
    // exactly; non-integer sources (Float32 ...) are quantized to this step.
    double quantization_step = 1.0;
    bool exact = false;
    // CRS, through PROJ: its name and EPSG code (empty / none without a CRS, or when PROJ
    // cannot read it: crs_note says why).
    std::string crs_name;
    std::optional<int> epsg;
    std::string crs_note;
    // What the heights are measured from: the archive's georeference.vertical_datum, else the
    // vertical part of its CRS (archives built before the key existed); none: unknown.
    std::optional<archive::VerticalDatumMetadata> vertical_datum;
    std::optional<ByteAccount> bytes; // readArchiveInfo(..., true) only
};

// Reads header, metadata and index; with `account_bytes`, every blob too (checked as read:
// its masks), for ArchiveInfo::bytes. Throws ridge::Error.
ArchiveInfo readArchiveInfo(const std::string& archive_path, bool account_bytes = false);

} // namespace ridge
