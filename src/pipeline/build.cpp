#include "ridge/pipeline/build.h"

#include "build_stages.h"
#include "build_streaming.h"

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
    // Decimation streams the finest level (memory ~ a quarter of the grid) with any codec
    // that may code it first (codecBuildsFinestFirst); voids, the Neville filter and codecs
    // that decode down a chain of parents (jpeg2000) need the whole grid in memory.
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
