#include "ridge/pipeline/build.h"

#include "build_stages.h"

#include "ridge/archive/archive_writer.h"
#include "ridge/archive/block_error_storage.h"
#include "ridge/archive/sample_flags_storage.h"
#include "ridge/archive/validity_storage.h"
#include "ridge/codec/height_codec.h"
#include "ridge/core/atomic_output.h"
#include "ridge/core/error.h"
#include "ridge/core/file_identity.h"
#include "ridge/core/json_text.h"
#include "ridge/io/dataset_files.h"
#include "ridge/pipeline/build_memory.h"
#include "ridge/pyramid/patch_context.h"
#include "ridge/pyramid/patch_error.h"
#include "ridge/pyramid/sample_flags.h"
#include "ridge/pyramid/tessellation_block_errors.h"
#include "ridge/pyramid/validity_pyramid.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>

namespace ridge {

namespace {

using namespace build_stages;

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start)
{
    return std::chrono::duration<double>(Clock::now() - start).count();
}

// Writes every patch of levels [0, last_level] from `pyramid` with the bounds in `errors`.
// Encodes `count` patches in parallel batches and writes them in order. `make(k)` encodes
// the k-th; `done(k, patch)` sees each after it was written (for bookkeeping).
void encodeAndWrite(int64_t count, const std::function<EncodedPatch(int64_t)>& make,
                    archive::ArchiveWriter& writer,
                    const std::function<void(int64_t, EncodedPatch&)>& done = {})
{
    encodeInOrder(count, make, [&](int64_t k, EncodedPatch& e) {
        writer.writePatch(e.record, e.block_errors, e.validity, e.sample_flags, e.payload.data(),
                          e.payload.size());
        if (done)
            done(k, e);
    });
}

void writeLevels(const BuildContext& ctx, const LevelPyramid& pyramid, int last_level,
                 const PatchErrors& errors, archive::ArchiveWriter& writer,
                 const Progress& progress)
{
    const PyramidGeometry& g = ctx.geometry;
    const int64_t count = g.firstPatchIndex(last_level) + g.patchCount(last_level);
    const LevelSpan levels{[&](int l) { return g.patchCount(l); },
                           [&](int l, int64_t k) { return g.patchAt(g.firstPatchIndex(l) + k); },
                           [&](PatchId p) { return g.patchIndex(p) - g.firstPatchIndex(p.level); }};
    std::vector<std::vector<uint16_t>> parents;
    int64_t written = 0;
    encodeTopDown(
        ctx, 0, last_level + 1, levels,
        [&](PatchId p, const uint16_t* parent) {
            const size_t index = size_t(g.patchIndex(p));
            const PatchSummary summary{errors.min_code[index], errors.max_code[index],
                                       errors.err_appr[index]};
            return encodePatch(ctx, pyramid.level(p.level), p, p, summary, parent);
        },
        [&](EncodedPatch& e) {
            writer.writePatch(e.record, e.block_errors, e.validity, e.sample_flags,
                              e.payload.data(), e.payload.size());
            if (++written % 64 == 0)
                reportProgress(progress, double(written) / double(count));
        },
        parents);
}

// The decimation build without ever holding the finest grid: the finest level is read in
// strips of two patch rows (2C+1 sample rows); each strip's finest patches are encoded and
// written at once, its even samples fill the materialised level L-1 (a quarter of the data),
// and level L-1's Err_Int is measured against it. Levels 0..L-1 are then built in memory from
// level L-1 exactly as the in-memory path would. Returns nullopt when the source has voids
// (they need the whole grid to be filled) or the pyramid has a single level.
std::optional<BuildReport> buildStreaming(const std::string& input, const std::string& output,
                                          const BuildOptions& options)
{
    const auto start = Clock::now();
    io::CodeRowReader source(input, options.ingest);
    BuildContext ctx =
        makeContext(source.width(), source.height(), source.quantization(), source.geo(), options);
    const PyramidGeometry& g = ctx.geometry;
    const int finest = g.finestLevel();
    if (finest == 0)
        return std::nullopt;
    const int cells = g.cells(), n = g.patchSize(), width = g.width(), height = g.height();

    archive::ArchiveWriter writer(output, ctx.header);
    PatchErrors errors = makePatchErrors(g);
    CodeGrid coarse; // level L-1, materialised
    coarse.width = g.levelWidth(finest - 1);
    coarse.height = g.levelHeight(finest - 1);
    coarse.codes.resize(static_cast<size_t>(coarse.width) * coarse.height);
    std::vector<uint16_t> strip(static_cast<size_t>(2 * cells + 1) * width);
    // Water (a sea level or a water layer): the strip's flags, and level L−1's, whose samples
    // are the finest at even positions, from which every coarser level's flags follow.
    const bool water = source.flagsWater();
    std::vector<uint8_t> strip_flags(water ? strip.size() : 0);
    SampleFlagsGrid coarse_flags =
        water ? SampleFlagsGrid(coarse.width, coarse.height) : SampleFlagsGrid();

    const int strips = g.patchesY(finest - 1);
    for (int k = 0; k < strips; ++k) {
        // 1. Read finest rows [2kC, 2kC + 2C] (the overlap row is read twice: 1/2C extra).
        const int y0 = 2 * k * cells;
        const int rows = std::min(2 * cells + 1, height - y0);
        if (source.readRows(y0, rows, strip.data(), water ? strip_flags.data() : nullptr) > 0)
            return std::nullopt;
        const LevelView strip_view{strip.data(), width, rows, 1, width, rows};

        // 2. The finest patches of the two patch rows in the strip.
        for (int half = 0; half < 2 && 2 * k + half < g.patchesY(finest); ++half) {
            const int py = 2 * k + half;
            encodeAndWrite(
                g.patchesX(finest),
                [&](int64_t x) {
                    PatchSampleFlags flags{PatchSampleFlags::Kind::None, n, {}};
                    if (water)
                        flags = windowPatchFlags(strip_flags.data(), width, rows, 1, n,
                                                 {finest, int(x), half});
                    return encodePatch(ctx, strip_view, {finest, int(x), half},
                                       {finest, int(x), py}, {}, nullptr, &flags);
                },
                writer,
                [&](int64_t x, EncodedPatch& e) {
                    const int64_t index = g.patchIndex({finest, int(x), py});
                    errors.min_code[index] = e.own_min;
                    errors.max_code[index] = e.own_max;
                });
        }

        // 3. Level L-1 rows [kC, kC + C]: the strip's even samples (clamped at the edges).
        const int j_end = std::min(k * cells + cells, coarse.height - 1);
        for (int j = k * cells; j <= j_end; ++j) {
            const uint16_t* src =
                strip.data() + static_cast<size_t>(std::min(2 * j - y0, rows - 1)) * width;
            uint16_t* dst = coarse.codes.data() + static_cast<size_t>(j) * coarse.width;
            for (int i = 0; i < coarse.width; ++i)
                dst[i] = src[std::min(2 * i, width - 1)];
            if (water) {
                const uint8_t* fsrc = strip_flags.data() + (src - strip.data());
                for (int i = 0; i < coarse.width; ++i)
                    coarse_flags.set(i, j, fsrc[std::min(2 * i, width - 1)]);
            }
        }

        // 4. Err_Int of level L-1's patch row k, against the strip.
        const int parent_rows = j_end - k * cells + 1;
        const LevelView parent_view{coarse.codes.data() +
                                        static_cast<size_t>(k) * cells * coarse.width,
                                    coarse.width,
                                    parent_rows,
                                    1,
                                    coarse.width,
                                    parent_rows};
#pragma omp parallel for schedule(dynamic, 1)
        for (int x = 0; x < g.patchesX(finest - 1); ++x)
            errors.err_int[g.patchIndex({finest - 1, x, k})] = static_cast<float>(
                interpolationError(parent_view, strip_view, n, {finest - 1, x, 0}));
        reportProgress(options.progress, 0.8 * double(k + 1) / strips);
    }

    // 5. Levels 0..L-1 from the materialised level L-1: same views, same patch indices.
    const LevelPyramid pyramid(coarse, PyramidGeometry(coarse.width, coarse.height, n),
                               PyramidFilter::Decimate);
    if (pyramid.geometry().levelCount() != finest)
        throw Error("internal error: level L-1 geometry mismatch");
    measurePatches(pyramid, 0, finest - 1, errors);
    accumulatePatchErrors(g, finest, errors);
    if (water)
        ctx.flags = std::make_unique<SampleFlagsPyramid>(std::move(coarse_flags), finest - 1, g);
    writeLevels(ctx, pyramid, finest - 1, errors, writer, subProgress(options.progress, 0.8, 1.0));
    writer.finish(metadataJson(input, source.stats(), source.geo(), ctx, options));
    reportDone(options.progress); // published: too late to cancel

    BuildReport report;
    report.width = width;
    report.height = height;
    report.level_count = g.levelCount();
    report.patch_count = g.patchCount();
    report.archive_bytes = writer.bytesWritten();
    report.quantization_error = ctx.header.quantization_error;
    report.streamed = true;
    report.seconds_total = secondsSince(start);
    return report;
}

// The in-memory build of an ingested raster, once the entry point has checked the options
// and the output (both public overloads do, first).
BuildReport buildFromRaster(const io::ElevationRaster& raster, const std::string& output,
                            const BuildOptions& options)
{
    const auto start = Clock::now();
    // 1. Geometry and codec: validates patch and block sizes before any work is done.
    BuildContext ctx = makeContext(raster.grid.width, raster.grid.height, raster.quantization,
                                   raster.geo, options);
    const LevelPyramid pyramid(raster.grid, ctx.geometry, options.filter);
    if (!raster.nodata.empty())
        ctx.validity =
            std::make_unique<ValidityPyramid>(raster.nodata, ctx.geometry, options.filter);
    if (!raster.flags.empty())
        ctx.flags = std::make_unique<SampleFlagsPyramid>(
            SampleFlagsGrid(raster.flags, raster.grid.width, raster.grid.height),
            ctx.geometry.finestLevel(), ctx.geometry);
    reportProgress(options.progress, 0.05);

    // 2. Err_Int for every patch, then Err_Appr bottom-up (needs all levels, so before writing).
    const PatchErrors errors = computePatchErrors(pyramid);
    BuildReport report;
    report.seconds_errors = secondsSince(start);
    reportProgress(options.progress, 0.25);

    // 3. A codec with per-archive tables learns them from every patch first.
    const auto t = Clock::now();
    trainCodec(ctx, pyramid);

    // 4. Encode in parallel batches, write sequentially.
    archive::ArchiveWriter writer(output, ctx.header);
    writer.setCodecTables(ctx.codec->storeTables());
    writeLevels(ctx, pyramid, ctx.geometry.finestLevel(), errors, writer,
                subProgress(options.progress, 0.25, 1.0));
    writer.finish(metadataJson(raster.source_path, raster.stats, raster.geo, ctx, options));
    reportDone(options.progress); // published: too late to cancel
    report.seconds_encode = secondsSince(t);
    report.seconds_total = secondsSince(start);

    report.width = ctx.geometry.width();
    report.height = ctx.geometry.height();
    report.level_count = ctx.geometry.levelCount();
    report.patch_count = ctx.geometry.patchCount();
    report.archive_bytes = writer.bytesWritten();
    report.voids_filled = raster.stats.voids_filled;
    report.voids_kept = raster.stats.voids_kept;
    report.quantization_error = raster.quantization.max_error;
    return report;
}

} // namespace

void BuildOptions::validate() const
{
    const PyramidGeometry probe(2, 2, patch_size); // throws for a size that is not 2^n+1
    if (!TessellationBlockLayout{patch_size, block_cells}.valid())
        throw Error("block_cells is " + std::to_string(block_cells) +
                    ": must be a power of two >= 2 dividing the patch's " +
                    std::to_string(patch_size - 1) + " cells");
    if (max_error)
        checkParameter("max_error", *max_error, kMaxErrorRange);
    ingest.validate();
}

BuildReport buildArchive(const std::string& input, const std::string& output,
                         const BuildOptions& options)
{
    options.validate();
    // Every file GDAL reads for the source and for the water layer.
    std::vector<std::string> inputs = io::datasetFiles(input);
    if (!options.ingest.water_layer.empty())
        for (std::string& file : io::datasetFiles(options.ingest.water_layer))
            inputs.push_back(std::move(file));
    refuseOutputOverInput(output, inputs);
    checkOutputWritable(output);
    // The raster's size and type, read without a sample: the memory check comes before any
    // allocation and before CodeRowReader's pre-pass over non-integer data.
    const io::RasterProbe probe = io::probeRaster(input, options.ingest);
    const AvailableMemory limit = buildMemoryLimit(options);
    // Decimation streams the finest level (memory ~ a quarter of the grid); voids and the
    // Neville filter need the whole grid in memory.
    // Progressive codecs code top-down, the finest level last; streaming writes it first,
    // so they take the in-memory path for now.
    const bool may_have_voids = probe.declares_nodata || probe.has_mask_band;
    if (buildStreams(options)) {
        checkBuildMemory(input, probe, estimateBuildMemory(probe, options, true, false), limit);
        if (std::optional<BuildReport> report = buildStreaming(input, output, options))
            return *report;
        // Voids found (or a single level): the whole grid after all.
        checkBuildMemory(input, probe, estimateBuildMemory(probe, options, false, true), limit);
    } else {
        checkBuildMemory(input, probe, estimateBuildMemory(probe, options, false, may_have_voids),
                         limit);
    }
    const auto start = Clock::now();
    io::IngestOptions ingest = options.ingest;
    ingest.progress = subProgress(options.progress, 0.0, 0.35);
    const io::ElevationRaster raster = io::ingestRaster(input, ingest);
    const double ingest_seconds = secondsSince(start);
    BuildOptions rest = options;
    rest.progress = subProgress(options.progress, 0.35, 1.0);
    BuildReport report = buildFromRaster(raster, output, rest);
    report.seconds_ingest = ingest_seconds;
    report.seconds_total = secondsSince(start);
    return report;
}

BuildReport buildArchive(const io::ElevationRaster& raster, const std::string& output,
                         const BuildOptions& options)
{
    options.validate();
    refuseOutputOverInput(output, {raster.source_path});
    checkOutputWritable(output);
    return buildFromRaster(raster, output, options);
}

} // namespace ridge
