#include "ridge/codecbench/codec_bench.h"
#include "ridge/pyramid/patch_context.h"

#include "ridge/archive/archive_reader.h"
#include "ridge/codec/codec_registry.h"
#include "ridge/codecbench/anchor_codec.h"
#include "ridge/core/error.h"
#include "ridge/pipeline/build.h"
#include "ridge/pipeline/build_memory.h"
#include "ridge/pipeline/level_decoder.h"
#include "ridge/stream/view_bytes.h"

#include <fmt/core.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <unistd.h>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace ridge::codecbench {

namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start)
{
    return std::chrono::duration<double>(Clock::now() - start).count();
}

// Runs ridge's OpenMP loops on one thread for the lifetime of the object, then restores the
// caller's setting: throughput is reported per core.
class SingleThreadScope {
  public:
    SingleThreadScope()
    {
#ifdef _OPENMP
        saved_ = omp_get_max_threads();
        omp_set_num_threads(1);
#endif
    }
    ~SingleThreadScope()
    {
#ifdef _OPENMP
        omp_set_num_threads(saved_);
#endif
    }
    SingleThreadScope(const SingleThreadScope&) = delete;
    SingleThreadScope& operator=(const SingleThreadScope&) = delete;

  private:
    int saved_ = 1;
};

// A path for ridge's archive that is removed when the object dies, whatever happens.
class ScratchArchive {
  public:
    explicit ScratchArchive(const std::string& dir)
    {
        static std::atomic<int> counter{0};
        const std::filesystem::path base =
            dir.empty() ? std::filesystem::temp_directory_path() : std::filesystem::path(dir);
        path_ =
            (base / fmt::format("ridge-codec-bench-{}-{}.ridge", ::getpid(), counter++)).string();
    }
    ~ScratchArchive()
    {
        std::error_code ec;
        std::filesystem::remove(path_, ec);
    }
    ScratchArchive(const ScratchArchive&) = delete;
    ScratchArchive& operator=(const ScratchArchive&) = delete;
    const std::string& path() const { return path_; }

  private:
    std::string path_;
};

// Accumulates |decoded - source| over the finest level, in code units.
struct ErrorTally {
    int64_t max_abs = 0;
    double sum_sq = 0.0;
    int64_t samples = 0;
    int64_t violations = 0;

    // `limit`: the largest |difference| in codes that keeps the bound.
    void add(const uint16_t* decoded, const uint16_t* source, size_t count, int64_t limit)
    {
        for (size_t i = 0; i < count; ++i) {
            const int64_t d = std::abs(int64_t{decoded[i]} - int64_t{source[i]});
            max_abs = std::max(max_abs, d);
            sum_sq += double(d) * double(d);
            violations += d > limit;
        }
        samples += int64_t(count);
    }
};

// The error and throughput columns, shared by ridge's row and the anchors'.
void finishRow(CodecRow& row, const ErrorTally& tally, const CodecBenchReport& report)
{
    const double samples = double(report.width) * double(report.height);
    const double scale = report.quantization.scale;
    row.ratio = row.bytes ? samples * 2.0 / double(row.bytes) : 0.0;
    row.bits_per_sample = 8.0 * double(row.bytes) / samples;
    row.max_error_codes = tally.max_abs;
    row.max_error_metres = double(tally.max_abs) * scale;
    row.rmse_metres = tally.samples ? std::sqrt(tally.sum_sq / double(tally.samples)) * scale : 0.0;
    const double peak = double(report.max_code - report.min_code) * scale;
    row.psnr_db = row.rmse_metres > 0.0 ? 20.0 * std::log10(peak / row.rmse_metres)
                                        : std::numeric_limits<double>::infinity();
    row.encode_mb_per_s =
        row.encode_seconds > 0.0 ? double(row.encode_bytes) / row.encode_seconds / 1e6 : 0.0;
    row.decode_mb_per_s =
        row.decode_seconds > 0.0 ? double(row.decode_bytes) / row.decode_seconds / 1e6 : 0.0;
    row.violations = tally.violations;
    row.bound_ok = tally.violations == 0;
}

// The cold-cache bytes of the typical views, on the renderer's own selection (untimed: it
// reads the index only).
std::vector<ViewBytesFigure> typicalViewBytes(const archive::ArchiveReader& reader,
                                              const CodecBenchOptions& options)
{
    const lod::PatchQuadtree quadtree = lod::PatchQuadtree::fromArchive(reader);
    const lod::SelectionSettings settings =
        stream::rendererSelectionSettings(options.view_epsilon_px, options.view_texel_px);
    std::vector<ViewBytesFigure> out;
    for (const stream::TypicalView view : stream::kTypicalViews) {
        const lod::Camera camera = stream::typicalViewCamera(
            quadtree, view, lod::Viewport{options.view_width, options.view_height});
        const stream::ViewBytes b = stream::viewBytes(reader, quadtree, camera, settings);
        out.push_back(
            {stream::typicalViewName(view), b.bytes, b.patches, b.selected, b.counts_ancestors});
    }
    return out;
}

// The codec alone on every payload of `reader`, level by level with the parents' codes
// (CodecRow::codec_decode_*).
void timeCodecDecode(const archive::ArchiveReader& reader, CodecRow& row)
{
    const PyramidGeometry& g = reader.geometry();
    const HeightCodec& codec = reader.codec();
    const int n = g.patchSize();
    const size_t samples = size_t(n) * n;
    std::vector<std::vector<uint16_t>> parents, current;
    std::vector<std::vector<uint8_t>> blobs;
    std::vector<size_t> offsets;
    for (int level = 0; level <= g.finestLevel(); ++level) {
        const int64_t first = g.firstPatchIndex(level), count = g.patchCount(level);
        blobs.assign(size_t(count), {});
        offsets.assign(size_t(count), 0);
        for (int64_t k = 0; k < count; ++k) {
            blobs[k] = reader.readBlob(g.patchAt(first + k));
            offsets[k] = reader.payloadOffset(g.patchAt(first + k), blobs[k]);
        }
        current.assign(size_t(count), std::vector<uint16_t>(samples));
        const Clock::time_point start = Clock::now();
        for (int64_t k = 0; k < count; ++k) {
            const PatchId p = g.patchAt(first + k);
            const uint16_t* parent =
                codec.needsParent(level)
                    ? parents[size_t(g.patchIndex(p.parent()) - g.firstPatchIndex(level - 1))]
                          .data()
                    : nullptr;
            const int status =
                codec.decode(current[k].data(), blobs[k].data() + offsets[k],
                             blobs[k].size() - offsets[k], patchContext(g, p, parent));
            if (status != kCodecOk)
                throw Error("ridge: " + reader.describe(p) + ": " + codecStatusMessage(status));
        }
        row.codec_decode_seconds += secondsSince(start);
        for (int64_t k = 0; k < count; ++k) {
            const PatchId p = g.patchAt(first + k);
            row.codec_decode_bytes +=
                uint64_t(g.coveredCellsX(p) + 1) * uint64_t(g.coveredCellsY(p) + 1) * 2;
        }
        parents.swap(current);
    }
    row.codec_decode_mb_per_s = row.codec_decode_seconds > 0 ? double(row.codec_decode_bytes) /
                                                                   row.codec_decode_seconds / 1e6
                                                             : 0.0;
}

// ridge's row: the whole pyramid built and decoded on one thread.
CodecRow runRidge(const io::ElevationRaster& raster, double bound_metres, const std::string& codec,
                  const CodecBenchOptions& options, const CodecBenchReport& report,
                  const Progress& progress)
{
    CodecRow row;
    row.codec = "ridge " + codec;
    row.scope = "pyramid";
    const ScratchArchive archive(options.scratch_dir);
    const SingleThreadScope single_thread;

    // 1. Build: the timed encode is everything buildArchive does from ingested codes.
    BuildOptions build;
    build.codec = codec;
    if (isLossyCodec(codec))
        build.max_error = bound_metres;
    build.progress = subProgress(progress, 0.0, 0.8);
    const Clock::time_point encode_start = Clock::now();
    buildArchive(raster, archive.path(), build);
    row.encode_seconds = secondsSince(encode_start);
    row.encode_bytes = uint64_t(raster.grid.codes.size()) * 2;

    // 2. Decode every level, as a renderer that streams the whole pyramid would.
    const Clock::time_point decode_start = Clock::now();
    const archive::ArchiveReader reader(archive.path());
    const int finest = reader.geometry().finestLevel();
    CodeGrid finest_grid;
    for (int level = 0; level <= finest; ++level) {
        CodeGrid grid = decodeLevel(reader, level);
        row.decode_bytes += uint64_t(grid.codes.size()) * 2;
        if (level == finest)
            finest_grid = std::move(grid);
    }
    row.decode_seconds = secondsSince(decode_start);
    timeCodecDecode(reader, row);
    row.bytes = reader.fileSize();
    row.view_bytes = typicalViewBytes(reader, options);
    reportProgress(progress, 0.9);

    // 3. Check the finest level against the source: ridge's bound is E in metres.
    if (finest_grid.width != raster.grid.width || finest_grid.height != raster.grid.height)
        throw Error(fmt::format("ridge: finest level decodes to {}x{}, source is {}x{}",
                                finest_grid.width, finest_grid.height, raster.grid.width,
                                raster.grid.height));
    const auto limit =
        int64_t(std::min(std::floor((bound_metres + 1e-9) / report.quantization.scale), 1e15));
    ErrorTally tally;
    tally.add(finest_grid.codes.data(), raster.grid.codes.data(), finest_grid.codes.size(), limit);
    finishRow(row, tally, report);
    reportProgress(progress, 1.0);
    return row;
}

// The finest level cut into tiles of at most `tile` x `tile` samples, row-major.
struct Tile {
    int width = 0;
    int height = 0;
    std::vector<uint16_t> codes;
};

std::vector<Tile> cutTiles(const CodeGrid& grid, int tile)
{
    const int tw = tile > 0 ? tile : grid.width;
    const int th = tile > 0 ? tile : grid.height;
    std::vector<Tile> tiles;
    for (int y0 = 0; y0 < grid.height; y0 += th)
        for (int x0 = 0; x0 < grid.width; x0 += tw) {
            Tile t;
            t.width = std::min(tw, grid.width - x0);
            t.height = std::min(th, grid.height - y0);
            t.codes.resize(size_t(t.width) * size_t(t.height));
            for (int y = 0; y < t.height; ++y)
                std::copy_n(&grid.codes[size_t(y0 + y) * size_t(grid.width) + size_t(x0)], t.width,
                            &t.codes[size_t(y) * size_t(t.width)]);
            tiles.push_back(std::move(t));
        }
    return tiles;
}

// Every `step`-th sample of every `step`-th row from (0, 0): a GIS overview by nearest
// sampling, and the samples ridge's decimation keeps at that step away from the far edges.
CodeGrid decimate(const CodeGrid& grid, int step)
{
    CodeGrid out;
    out.width = (grid.width - 1) / step + 1;
    out.height = (grid.height - 1) / step + 1;
    out.codes.resize(size_t(out.width) * size_t(out.height));
    for (int y = 0; y < out.height; ++y)
        for (int x = 0; x < out.width; ++x)
            out.at(x, y) = grid.at(x * step, y * step);
    return out;
}

// The overviews CodecBenchOptions::overviews describes, coarser in turn: while the level
// before is larger than `min_size` on either side, the grid decimated by the next power of 2.
std::vector<CodeGrid> overviewGrids(const CodeGrid& grid, int min_size)
{
    std::vector<CodeGrid> levels;
    for (int step = 2;; step *= 2) {
        const CodeGrid& before = levels.empty() ? grid : levels.back();
        if (std::max(before.width, before.height) <= min_size)
            break;
        levels.push_back(decimate(grid, step));
    }
    return levels;
}

// An anchor's row over `levels` (the finest level's tiles, then any overviews'; `overviews`
// names the row so even when the grid needs none): every tile encoded, then decoded, each
// call timed on its own so that the bound check and bookkeeping stay outside the clock.
// Errors are tallied over every level.
CodecRow runAnchor(const AnchorCodec& anchor, const std::vector<const std::vector<Tile>*>& levels,
                   bool overviews, int e, const CodecBenchReport& report, const Progress& progress)
{
    CodecRow row;
    row.codec = anchor.name() + (overviews ? " + overviews" : "");
    row.scope = overviews ? "with overviews" : "finest level";
    std::vector<const Tile*> tiles;
    for (const std::vector<Tile>* level : levels)
        for (const Tile& t : *level)
            tiles.push_back(&t);
    std::vector<std::vector<uint8_t>> streams(tiles.size());
    for (size_t i = 0; i < tiles.size(); ++i) {
        const Tile& t = *tiles[i];
        const Clock::time_point start = Clock::now();
        streams[i] = anchor.encode(t.codes.data(), t.width, t.height, e);
        row.encode_seconds += secondsSince(start);
        row.bytes += streams[i].size();
        row.encode_bytes += uint64_t(t.codes.size()) * 2;
        reportProgress(progress, 0.5 * double(i + 1) / double(tiles.size()));
    }
    ErrorTally tally;
    std::vector<uint16_t> decoded;
    for (size_t i = 0; i < tiles.size(); ++i) {
        const Tile& t = *tiles[i];
        decoded.assign(t.codes.size(), 0);
        const Clock::time_point start = Clock::now();
        anchor.decode(streams[i].data(), streams[i].size(), t.width, t.height, e, decoded.data());
        row.decode_seconds += secondsSince(start);
        row.decode_bytes += uint64_t(t.codes.size()) * 2;
        tally.add(decoded.data(), t.codes.data(), t.codes.size(), e);
        reportProgress(progress, 0.5 + 0.5 * double(i + 1) / double(tiles.size()));
    }
    finishRow(row, tally, report);
    return row;
}

// Whether `spec` names a codec mode without a bound (the fractal paper's): archives refuse
// it, so its row codes the anchors' tiles, each as one patch.
bool unboundedCodec(const std::string& spec)
{
    return !std::isfinite(makeCodec(spec, 1.0, 1)->levelErrorBound(0));
}

// A ridge codec without a bound, on the anchors' tiles: each tile one square patch (the last
// row and column repeated to its side), encoded and decoded through HeightCodec, each call
// timed. Its error is measured, not promised (scope "tiles, no bound").
CodecRow runRidgeTiles(const std::string& spec, const std::vector<Tile>& tiles, int e,
                       const CodecBenchReport& report, const Progress& progress)
{
    CodecRow row;
    row.codec = "ridge " + spec;
    row.scope = "tiles, no bound";
    row.bounded = false;
    const std::unique_ptr<HeightCodec> codec = makeCodec(spec, 0.0, 1);
    std::vector<uint8_t> payload;
    std::vector<uint16_t> patch, decoded, region;
    ErrorTally tally;
    for (size_t i = 0; i < tiles.size(); ++i) {
        const Tile& t = tiles[i];
        const int n = std::max(t.width, t.height);
        patch.assign(size_t(n) * size_t(n), 0);
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x)
                patch[size_t(y) * size_t(n) + size_t(x)] =
                    t.codes[size_t(std::min(y, t.height - 1)) * size_t(t.width) +
                            size_t(std::min(x, t.width - 1))];
        const PatchContext ctx{n, 0, nullptr, 0, t.width, t.height};
        payload.resize(codec->encodeBound(ctx));
        Clock::time_point start = Clock::now();
        const size_t size = codec->encode(payload.data(), payload.size(), patch.data(), ctx);
        row.encode_seconds += secondsSince(start);
        if (size == 0)
            throw Error("ridge " + spec + ": a tile does not encode");
        row.bytes += size;
        row.encode_bytes += uint64_t(t.codes.size()) * 2;
        decoded.assign(patch.size(), 0);
        start = Clock::now();
        const int status = codec->decode(decoded.data(), payload.data(), size, ctx);
        row.decode_seconds += secondsSince(start);
        if (status != kCodecOk)
            throw Error("ridge " + spec +
                        ": a tile does not decode: " + codecStatusMessage(status));
        row.decode_bytes += uint64_t(t.codes.size()) * 2;
        region.resize(t.codes.size());
        for (int y = 0; y < t.height; ++y)
            std::copy_n(&decoded[size_t(y) * size_t(n)], t.width,
                        &region[size_t(y) * size_t(t.width)]);
        tally.add(region.data(), t.codes.data(), t.codes.size(), e);
        reportProgress(progress, double(i + 1) / double(tiles.size()));
    }
    finishRow(row, tally, report);
    return row;
}

std::string cpuModel()
{
    std::ifstream in("/proc/cpuinfo");
    std::string line;
    while (std::getline(in, line))
        if (line.rfind("model name", 0) == 0) {
            const auto colon = line.find(':');
            if (colon != std::string::npos) {
                const auto start = line.find_first_not_of(" \t", colon + 1);
                return start == std::string::npos ? "unknown" : line.substr(start);
            }
        }
    return "unknown";
}

void validate(const CodecBenchOptions& options)
{
    if (options.max_errors.empty())
        throw Error("max_errors: at least one bound is needed");
    for (size_t k = 0; k < options.max_errors.size(); ++k)
        checkParameter("max_errors[" + std::to_string(k) + "] (metres)", options.max_errors[k],
                       CodecBenchOptions::kMaxErrorRange);
    checkParameter("tile_size", int64_t{options.tile_size}, 0, CodecBenchOptions::kMaxTileSize);
    checkParameter("overview_min_size", int64_t{options.overview_min_size}, 1,
                   CodecBenchOptions::kMaxOverviewMinSize);
    if (options.ridge_codecs.empty())
        throw Error("ridge_codecs: at least one codec is needed");
    for (const std::string& codec : options.ridge_codecs)
        if (const std::string problem = codecSpecProblem(codec); !problem.empty())
            throw Error("ridge_codecs " + codec + ": " + problem);
    checkParameter("view_width", int64_t{options.view_width}, 1, CodecBenchOptions::kMaxViewPixels);
    checkParameter("view_height", int64_t{options.view_height}, 1,
                   CodecBenchOptions::kMaxViewPixels);
    checkParameter("view_epsilon_px", options.view_epsilon_px,
                   lod::SelectionSettings::kEpsilonPxRange);
    checkParameter("view_texel_px", options.view_texel_px, lod::SelectionSettings::kTexelPxRange);
}

// The bench ingests the whole raster, copies it into tiles and builds ridge's archive of it in
// memory: refuse, before anything is allocated, a raster whose in-memory build alone (plus the
// tile copy) cannot fit what is available. A lower bound: the anchors' streams come on top.
void checkCodecBenchMemory(const std::string& input, const io::IngestOptions& ingest)
{
    const io::RasterProbe probe = io::probeRaster(input, ingest);
    BuildOptions as_built;
    as_built.codec = "progressive";
    BuildMemoryEstimate e =
        estimateBuildMemory(probe, as_built, false, probe.declares_nodata || probe.has_mask_band);
    e.terms.push_back({"tiles", uint64_t(probe.width) * uint64_t(probe.height) * 2});
    const AvailableMemory available = availableMemory();
    if (e.total() <= available.bytes)
        return;
    throw Error(input + ": " + std::to_string(probe.width) + " x " + std::to_string(probe.height) +
                " samples need at least " + formatBytes(e.total()) + " to benchmark (" +
                e.describe() + "; tiles), but " + formatBytes(available.bytes) +
                " are available (" + available.source + ")");
}

} // namespace

CodecBenchReport runCodecBench(const std::string& input, const CodecBenchOptions& options)
{
    validate(options);
    checkCodecBenchMemory(input, options.ingest);
    io::IngestOptions ingest = options.ingest;
    ingest.progress = subProgress(options.progress, 0.0, 0.05);
    const io::ElevationRaster raster = io::ingestRaster(input, ingest);
    CodecBenchOptions rest = options;
    rest.progress = subProgress(options.progress, 0.05, 1.0);
    return runCodecBench(raster, rest);
}

CodecBenchReport runCodecBench(const io::ElevationRaster& raster, const CodecBenchOptions& options)
{
    validate(options);
    const CodeGrid& grid = raster.grid;
    if (grid.width <= 0 || grid.height <= 0 ||
        grid.codes.size() != size_t(grid.width) * size_t(grid.height))
        throw Error(raster.source_path + ": empty or inconsistent grid");

    // 1. What is being compared, on what, with what.
    CodecBenchReport report;
    report.input_path = raster.source_path;
    report.width = grid.width;
    report.height = grid.height;
    report.quantization = raster.quantization;
    const auto [lo, hi] = std::minmax_element(grid.codes.begin(), grid.codes.end());
    report.min_code = *lo;
    report.max_code = *hi;
    report.tile_size = options.tile_size;
    report.ridge_codecs = options.ridge_codecs;
    report.cpu_model = cpuModel();
    report.threads = 1;
    report.view_width = options.view_width;
    report.view_height = options.view_height;
    report.view_epsilon_px = options.view_epsilon_px;
    report.view_texel_px = options.view_texel_px;
    const auto anchors = makeAnchorCodecs();
    // Which of ridge's codecs have no bound (their rows code tiles), decided once.
    std::vector<bool> unbounded;
    for (const std::string& codec : options.ridge_codecs)
        unbounded.push_back(unboundedCodec(codec));
    for (size_t k = 0; k < options.ridge_codecs.size(); ++k) {
        const std::string& codec = options.ridge_codecs[k];
        report.codecs.push_back(
            {"ridge " + codec,
             fmt::format("ridge 0.1.0, archive format v{}", archive::kFormatVersion),
             unbounded[k] ? "the anchors' tiles, one patch each, no bound (its errors are measured)"
             : isLossyCodec(codec)
                 ? "whole pyramid, BuildOptions defaults (patch 129, block 8, decimation), "
                   "max_error = E metres end to end"
                 : "whole pyramid, BuildOptions defaults (patch 129, block 8, decimation), "
                   "lossless",
             !unbounded[k]});
    }
    for (const auto& a : anchors)
        report.codecs.push_back(
            {a->name(), a->libraryVersion(), a->description(), a->guaranteesBound()});

    // 2. Tiles are cut once: every anchor and every bound sees the same tiles, and the same
    // overviews' tiles when asked for.
    const std::vector<Tile> tiles = cutTiles(grid, options.tile_size);
    std::vector<std::vector<Tile>> overview_tiles;
    // The anchors that get a "+ overviews" row: a progressive one holds its pyramid already.
    std::vector<const AnchorCodec*> single_level;
    if (options.overviews) {
        for (const auto& a : anchors)
            if (!a->progressive())
                single_level.push_back(a.get());
        for (const CodeGrid& level : overviewGrids(grid, options.overview_min_size)) {
            report.overview_sizes.emplace_back(level.width, level.height);
            overview_tiles.push_back(cutTiles(level, options.tile_size));
        }
        for (const AnchorCodec* a : single_level)
            report.codecs.push_back(
                {a->name() + " + overviews", a->libraryVersion(),
                 a->description() +
                     fmt::format("; on the finest level and its {} overviews (every 2^k-th "
                                 "sample, down to {} samples a side), each level in those tiles",
                                 overview_tiles.size(), options.overview_min_size),
                 a->guaranteesBound()});
    }
    std::vector<const std::vector<Tile>*> finest_level{&tiles}, with_overviews{&tiles};
    for (const std::vector<Tile>& level : overview_tiles)
        with_overviews.push_back(&level);

    // 3. Each bound: ridge's pyramid, then every anchor on the finest level (and again each
    // single-level one with its overviews).
    const size_t anchor_rows = anchors.size() + single_level.size();
    const double steps =
        double(options.max_errors.size() * (anchor_rows + options.ridge_codecs.size()));
    double step = 0.0;
    const auto stepProgress = [&] {
        const Progress p = subProgress(options.progress, step / steps, (step + 1.0) / steps);
        step += 1.0;
        return p;
    };
    for (const double bound : options.max_errors) {
        BoundResult result;
        result.max_error_metres = bound;
        const double codes = std::floor(bound / raster.quantization.scale + 1e-9);
        result.max_error_codes = int(std::min(codes, 65535.0));
        for (size_t k = 0; k < options.ridge_codecs.size(); ++k) {
            const std::string& codec = options.ridge_codecs[k];
            result.rows.push_back(
                unbounded[k]
                    ? runRidgeTiles(codec, tiles, result.max_error_codes, report, stepProgress())
                    : runRidge(raster, bound, codec, options, report, stepProgress()));
        }
        for (const auto& a : anchors)
            result.rows.push_back(
                runAnchor(*a, finest_level, false, result.max_error_codes, report, stepProgress()));
        for (const AnchorCodec* a : single_level)
            result.rows.push_back(runAnchor(*a, with_overviews, true, result.max_error_codes,
                                            report, stepProgress()));
        report.bounds.push_back(std::move(result));
    }
    reportProgress(options.progress, 1.0);
    return report;
}

} // namespace ridge::codecbench
