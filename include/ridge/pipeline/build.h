#pragma once
// `ridge build`: raster -> patch quadtree -> .ridge archive.
#include "ridge/core/progress.h"
#include "ridge/io/raster_source.h"
#include "ridge/pyramid/level_pyramid.h"

#include <cstdint>
#include <optional>
#include <string>

namespace ridge {

struct BuildOptions {
    int patch_size = 129;           // 2^n + 1
    int block_cells = 8;            // tessellation block: 8 cells = 9x9 samples
    std::string codec = "lossless"; // a codec spec (ridge/codec/codec_registry.h)
    // Lossy codecs (progressive): the end-to-end L-inf bound at the finest level in metres,
    // ingest quantization included; level l gets 2^(L-1-l) times that (delta_l of the paper).
    std::optional<double> max_error;
    PyramidFilter filter = PyramidFilter::Decimate;
    // Tessellation block errors λ(d) stored in each blob. Off by default: readers derive
    // them exactly from the decoded heights (~10% of a compressed archive saved).
    bool store_block_errors = false;
    io::IngestOptions ingest; // spacing, z-scale/offset, max_error (quantization)
    // The memory the build may use, bytes; 0: what the system has available
    // (availableMemory(): MemAvailable, the cgroup limit, RLIMIT_AS, RLIMIT_DATA). A raster
    // whose estimate (pipeline/build_memory.h) exceeds it is refused before anything is
    // allocated.
    uint64_t memory_limit_bytes = 0;
    Progress progress;

    // Lossy codecs' max_error: positive, and no larger than a height may be.
    static constexpr ValueRange kMaxErrorRange = io::IngestOptions::kMaxErrorRange;
    // Throws ridge::Error naming the first option outside its range: patch_size (2^n+1),
    // block_cells, max_error, ingest (IngestOptions::validate). buildArchive calls it first.
    void validate() const;
};

struct BuildReport {
    int width = 0;
    int height = 0;
    int level_count = 0;
    int64_t patch_count = 0;
    uint64_t archive_bytes = 0;
    int64_t voids_filled = 0;
    int64_t voids_kept = 0; // nodata kept as nodata (BuildOptions::ingest.fill_voids)
    double quantization_error = 0.0;
    bool streamed = false; // built strip by strip (decimation, no voids)
    double seconds_total = 0.0;
    double seconds_ingest = 0.0;
    double seconds_errors = 0.0;
    double seconds_encode = 0.0;
};

// Builds `output` from `input`. Throws ridge::Error (input or output problem) or
// ridge::Cancelled; in both cases nothing is left at `output`.
// Memory: with the decimation filter and a void-free source, the finest level is streamed in
// strips and only level L-1 (a quarter of the samples, 2 bytes each) is held; with voids or
// the Neville filter the whole grid is held (2 bytes per sample, +1/3 for Neville). Before
// allocating, the path's needs are estimated from the raster's declared size
// (pipeline/build_memory.h) and a raster that does not fit memory_limit_bytes (or what is
// available) is refused with an Error naming the file, its size and both amounts; the
// fallback from streaming to in memory (voids found) checks again before ingesting.
BuildReport buildArchive(const std::string& input, const std::string& output,
                         const BuildOptions& options);

// Same from an already ingested raster (tests, embedding applications); no memory check
// (the grid is already held).
BuildReport buildArchive(const io::ElevationRaster& raster, const std::string& output,
                         const BuildOptions& options);

} // namespace ridge
