#pragma once
// `ridge codec-bench`: ridge's codecs against the strongest error-bounded anchor codecs
// (anchor_codec.h) on the same raster and the same L-inf bound.
//
// For every bound E (metres) the bench
//   1. builds ridge's whole pyramid with BuildOptions::max_error = E into a temporary archive
//      and decodes every level back (ridge's bound is end-to-end in metres);
//   2. codes the finest level with every anchor in independent tiles, with the same integer
//      bound e = floor(E / scale + 1e-9) code units (scale: metres per code);
//   3. checks every decoded finest-level sample against the ingested codes and measures
//      bytes, max error, RMSE, PSNR and per-core throughput.
// Everything runs on one thread (OpenMP is set to 1 thread around ridge's build and decode
// and restored after), so MB/s compare codecs, not core counts.
//
// Sizes are not like for like, by design: ridge's bytes are the whole archive (every coarser
// level, index, λ tables, metadata); an anchor's are the finest level only. The table says so.
#include "ridge/core/height_grid.h"
#include "ridge/core/parameter_check.h"
#include "ridge/core/progress.h"
#include "ridge/io/raster_source.h"

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace ridge::codecbench {

struct CodecBenchOptions {
    // The ranges validation enforces (the CLI's flags use them too, so --help states them): a
    // bound is a positive height difference (ridge's lossy build needs one; its lossless row
    // is --ridge-codec lossless); a tile is at most a GL-sized 65536 samples across.
    static constexpr ValueRange kMaxErrorRange = ValueRange::openClosed(0.0, kMaxAbsHeightMetres);
    static constexpr int kMaxTileSize = 65536;

    // L-inf bounds in metres (kMaxErrorRange), at least one, in the order they are reported.
    std::vector<double> max_errors{0.5, 1.0, 4.0, 16.0};
    // Anchors' tile side in samples (edge tiles are smaller), at most kMaxTileSize; 0 = the
    // whole grid as one tile.
    int tile_size = 256;
    // ridge's codecs, one row each (before the anchors'), as `ridge build --codec` spells them
    // (ridge/codec/codec_registry.h), at least one. A lossy codec is built with
    // BuildOptions::max_error = E; a lossless one without it, once per bound.
    std::vector<std::string> ridge_codecs{"progressive"};
    // Also code every anchor's overviews, as a GIS pyramid (a COG with overviews) carries
    // them: the finest level decimated by 2, 4, 8, ... (every 2^k-th sample of every 2^k-th
    // row) until the larger side is at most overview_min_size samples (gdaladdo's rule
    // without explicit levels, -minsize), each level in the anchor's tiles. One more row per
    // anchor, "<anchor> + overviews", scope "with overviews": what a single-level format pays
    // for the levels of detail ridge's archive holds.
    bool overviews = false;
    static constexpr int kMaxOverviewMinSize = 65536;
    int overview_min_size = 256; // [1, kMaxOverviewMinSize]
    // Directory for ridge's temporary archive; empty = the system temporary directory.
    std::string scratch_dir;
    // Bytes fetched per view (ridge/stream/view_bytes.h) for ridge's row: the typical near,
    // mid and far views at this viewport, ε and texel target (the renderer's defaults).
    static constexpr int kMaxViewPixels = 65536;
    int view_width = 1920; // pixels, [1, kMaxViewPixels]
    int view_height = 1080;
    double view_epsilon_px = 2.0; // lod::SelectionSettings::kEpsilonPxRange
    double view_texel_px = 1.0;   // lod::SelectionSettings::kTexelPxRange (0: off)
    // Ingest settings for runCodecBench(path, ...) (z-scale, spacing, quantization).
    io::IngestOptions ingest;
    // Completed fraction of the whole bench; returning false cancels (ridge::Cancelled).
    Progress progress;
};

// What a cold cache reads to draw one typical view of ridge's archive (stream::viewBytes).
struct ViewBytesFigure {
    std::string view;      // "near", "mid", "far" (stream::typicalViewName)
    uint64_t bytes = 0;    // blob bytes, selected patches and (progressive) their ancestors
    uint64_t patches = 0;  // distinct patches read
    uint64_t selected = 0; // patches the renderer's selection draws
    bool counts_ancestors = false;
};

// One codec at one bound.
struct CodecRow {
    std::string codec;            // "ridge progressive", "LERC", ...
    std::string scope;            // "pyramid" (ridge), "finest level" or "with overviews" (anchors)
    uint64_t bytes = 0;           // ridge: archive file size; anchors: sum over tiles (and levels)
    double ratio = 0.0;           // finest level as 16-bit samples (width * height * 2) / bytes
    double bits_per_sample = 0.0; // 8 * bytes / (width * height)
    int64_t max_error_codes = 0;  // largest |decoded - source| on the finest level (overview
                                  // rows: on every level they code)
    double max_error_metres = 0.0;
    double rmse_metres = 0.0;
    double psnr_db = 0.0;         // 20 log10(peak / RMSE), peak = max - min height; +inf if exact
    double encode_seconds = 0.0;  // ridge: buildArchive wall time; anchors: sum over tiles
    double decode_seconds = 0.0;  // ridge: open + decodeLevel of every level
    uint64_t encode_bytes = 0;    // 16-bit samples consumed by the encoder (finest level)
    uint64_t decode_bytes = 0;    // 16-bit samples produced (ridge: all levels)
    double encode_mb_per_s = 0.0; // 10^6 bytes per second, one core
    double decode_mb_per_s = 0.0;
    // ridge's row only: the codec alone (HeightCodec::decode of every payload, top-down with
    // each parent's reconstruction, blobs already in memory; no archive I/O, checksums, λ or
    // masks). Bytes: the 16-bit samples each patch covers (PyramidGeometry::coveredCells + 1
    // per axis), padding not counted. 0 for the anchors, whose dec MB/s is already that.
    double codec_decode_seconds = 0.0;
    uint64_t codec_decode_bytes = 0;
    double codec_decode_mb_per_s = 0.0;
    int64_t violations = 0; // finest-level samples outside the bound
    bool bound_ok = true;
    bool bounded = true; // false: a codec mode without a bound (errors measured, not promised)
    // ridge's row only (empty for anchors, which have no pyramid to select from): near, mid,
    // far at CodecBenchReport::view_*.
    std::vector<ViewBytesFigure> view_bytes;
};

struct BoundResult {
    double max_error_metres = 0.0; // E, ridge's end-to-end bound
    int max_error_codes = 0;       // e, every anchor's bound
    // ridge's codecs first, then the anchors in makeAnchorCodecs() order, then (with
    // CodecBenchOptions::overviews) the anchors again with their overviews, in that order.
    std::vector<CodecRow> rows;
};

// A codec as the report describes it.
struct CodecInfo {
    std::string codec;         // as in CodecRow::codec
    std::string library;       // library and version
    std::string configuration; // how it is driven
    bool guarantees_bound = true;
};

struct CodecBenchReport {
    std::string input_path;
    int width = 0;
    int height = 0;
    HeightQuantization quantization;
    uint16_t min_code = 0; // of the ingested finest level
    uint16_t max_code = 0;
    int tile_size = 0; // as requested (0 = whole grid)
    // The anchors' overviews as coded (CodecBenchOptions::overviews), width and height of
    // each, the finest level's first overview first; empty when none were asked for or the
    // finest level is already within overview_min_size.
    std::vector<std::pair<int, int>> overview_sizes;
    std::vector<std::string> ridge_codecs;
    std::string cpu_model; // /proc/cpuinfo "model name", "unknown" when absent
    int threads = 1;       // threads every codec ran on
    int view_width = 0;    // CodecBenchOptions::view_* as run
    int view_height = 0;
    double view_epsilon_px = 0.0;
    double view_texel_px = 0.0;
    std::vector<CodecInfo> codecs;
    std::vector<BoundResult> bounds;

    double minMetres() const { return quantization.toMetres(min_code); }
    double maxMetres() const { return quantization.toMetres(max_code); }
};

// Ingests `input` with options.ingest and runs the bench. Throws ridge::Error naming the
// file for unreadable input, naming the option for an invalid bound or tile size, naming the
// codec when a library fails; ridge::Cancelled through options.progress. A bound that a codec
// misses is not an error: its row says VIOLATED. Before ingesting, a raster whose in-memory
// build and tile copy cannot fit the memory available (ridge/core/system_memory.h) is refused
// naming its size and both amounts.
// Cost: each bound builds and decodes ridge's pyramid once and codes the finest level once
// per anchor; memory about 3x the finest level as 16-bit codes.
CodecBenchReport runCodecBench(const std::string& input, const CodecBenchOptions& options);

// Same from an already ingested raster (tests, embedding applications).
CodecBenchReport runCodecBench(const io::ElevationRaster& raster, const CodecBenchOptions& options);

// Plain-text tables, one per bound, with footnotes on scope, units and configurations.
std::string formatCodecBenchTable(const CodecBenchReport& report);

// Every number of the report, machine and library information, as a JSON document.
// PSNR of an exact reconstruction is written as null (JSON has no infinity).
std::string formatCodecBenchJson(const CodecBenchReport& report);

// Writes formatCodecBenchJson to `path` atomically. Throws ridge::Error naming the path.
void writeCodecBenchJson(const CodecBenchReport& report, const std::string& path);

// Compression ratio against the error bound (metres, log2 axis), one curve per codec, as a
// PNG written atomically to `path`. Throws ridge::Error naming the path.
void writeCodecBenchPlot(const CodecBenchReport& report, const std::string& path);

} // namespace ridge::codecbench
