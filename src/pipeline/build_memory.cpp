#include "ridge/pipeline/build_memory.h"

#include "ridge/archive/format.h"
#include "ridge/codec/height_codec.h"
#include "ridge/core/error.h"
#include "ridge/pyramid/pyramid_geometry.h"

#include <algorithm>
#include <thread>

namespace ridge {

namespace {

// GDALFillNodata keeps its three work rasters in memory up to this many samples (5 B each);
// larger windows go to temporary files (src/io/void_fill.cpp, kInMemoryWorkSamples).
constexpr uint64_t kFillInMemorySamples = uint64_t{16} << 20;
// Strips of source values ingest reads at a time (src/io/code_source.h, kStripBytes), in
// doubles for non-integer types.
constexpr uint64_t kIngestStripBytes = uint64_t{8} << 20;

uint64_t levelSamples(const PyramidGeometry& g, int level)
{
    return uint64_t(g.levelWidth(level)) * uint64_t(g.levelHeight(level));
}

// Writer records, the serialised index written at finish(), PatchErrors, written flags.
uint64_t indexAndErrorBytes(const PyramidGeometry& g)
{
    const uint64_t per_patch = sizeof(archive::PatchRecord) + archive::kIndexEntrySize +
                               2 * sizeof(float) + 2 * sizeof(uint16_t);
    return uint64_t(g.patchCount()) * per_patch + uint64_t(g.patchCount()) / 8;
}

// A batch of encoded patches (codes-sized payload bound, reconstruction when lossy) and
// each thread's patch and λ buffers.
uint64_t encodeBatchBytes(const PyramidGeometry& g, bool lossy)
{
    const uint64_t patch = uint64_t(g.patchSize()) * uint64_t(g.patchSize()) * 2;
    const uint64_t threads = std::max(1u, std::thread::hardware_concurrency());
    return uint64_t(kEncodeBatchPatches) * patch * (lossy ? 3 : 2) + threads * patch * 3;
}

// Progressive codecs code level l from level l-1's reconstructions, kept until level l is
// written while level l's are kept for l+1: the widest two consecutive levels up to
// `last_level`, the last level coded top down (a streamed build codes the finest from level
// L−1's codes instead).
uint64_t reconstructionBytes(const PyramidGeometry& g, int last_level)
{
    const uint64_t patch = uint64_t(g.patchSize()) * uint64_t(g.patchSize()) * 2;
    uint64_t widest = 0;
    for (int l = 1; l <= last_level; ++l) {
        const uint64_t kept =
            uint64_t(g.patchCount(l - 1)) + (l < last_level ? uint64_t(g.patchCount(l)) : 0);
        widest = std::max(widest, kept);
    }
    return widest * patch;
}

uint64_t sumOf(const std::vector<MemoryTerm>& terms)
{
    uint64_t total = 0;
    for (const MemoryTerm& t : terms)
        total += t.bytes;
    return total;
}

BuildMemoryEstimate streamingEstimate(const io::RasterProbe& raster, const PyramidGeometry& g,
                                      bool lossy)
{
    const uint64_t width = uint64_t(raster.width);
    const int coarse = std::max(0, g.finestLevel() - 1);
    const uint64_t strip_rows = 2 * uint64_t(g.cells()) + 1;
    BuildMemoryEstimate e;
    e.streaming = true;
    e.terms = {
        {"level L-1 in memory", levelSamples(g, coarse) * 2},
        {"index and errors", indexAndErrorBytes(g)},
        {"source strip and GDAL cache",
         strip_rows * width * (2 + uint64_t(raster.strip_extra_bytes_per_sample)) +
             uint64_t(raster.block_cache_bytes)},
        // Water (the default sea level, or a layer): the strip's flags and level L−1's.
        {"sample flags", strip_rows * width * 2 + levelSamples(g, coarse) / 4},
        {"encode batches", encodeBatchBytes(g, lossy)},
        {"program and libraries", kBaselineBytes},
    };
    if (lossy) // codes levels 0..L−1 top down once the finest is written
        e.terms.push_back({"progressive reconstructions", reconstructionBytes(g, coarse)});
    return e;
}

BuildMemoryEstimate inMemoryEstimate(const io::RasterProbe& raster, const PyramidGeometry& g,
                                     const BuildOptions& options, bool voids)
{
    const uint64_t samples = uint64_t(raster.width) * uint64_t(raster.height);
    const MemoryTerm grid{"whole grid", samples * 2};
    const MemoryTerm baseline{"program and libraries", kBaselineBytes};

    // The sample flags (water, filled: 1 B/sample) from ingest through the build, and their
    // 2-bit grid while patches are encoded.
    const MemoryTerm flags{"sample flags", samples + samples / 4};
    std::vector<MemoryTerm> ingest = {grid, baseline, flags};
    ingest.push_back(
        {"source strip and GDAL cache",
         kIngestStripBytes * (raster.direct_codes ? 1 : 2) + uint64_t(raster.block_cache_bytes)});
    if (voids)
        ingest.push_back({"void filling", samples + std::min(samples, kFillInMemorySamples) * 5});
    // Voids kept as nodata: ElevationRaster::nodata (1 B/sample) through ingest and build, and
    // the ValidityPyramid's sample and cell grids (1 bit each per sample of every level, ≈ 1/3
    // B per finest sample) while the patches are encoded.
    const bool keeps = voids && options.ingest.fill_voids != io::VoidFill::All;
    if (keeps)
        ingest.push_back({"kept-nodata mask", samples});

    // Neville's first coarsening filters the grid's rows into floats (height x level L-1's
    // width, 4 B each: as much as the grid itself) before its columns make level L-1.
    std::vector<MemoryTerm> coarsening = {grid, baseline};
    std::vector<MemoryTerm> build = {grid, baseline, flags};
    if (options.filter == PyramidFilter::Neville4 && g.finestLevel() > 0) {
        const int coarse = g.finestLevel() - 1;
        coarsening.push_back(
            {"Neville row pass", uint64_t(raster.height) * uint64_t(g.levelWidth(coarse)) * 4});
        coarsening.push_back({"Neville levels", levelSamples(g, coarse) * 2});
        uint64_t coarser = 0;
        for (int l = 0; l < g.finestLevel(); ++l)
            coarser += levelSamples(g, l);
        build.push_back({"Neville levels", coarser * 2});
    }
    build.push_back({"index and errors", indexAndErrorBytes(g)});
    if (keeps) {
        uint64_t level_samples = 0;
        for (int l = 0; l <= g.finestLevel(); ++l)
            level_samples += levelSamples(g, l);
        build.push_back(
            {"kept-nodata mask and validity grids", samples + (2 * level_samples + 7) / 8});
    }
    const bool lossy = isLossyCodec(options.codec);
    if (lossy)
        build.push_back({"progressive reconstructions", reconstructionBytes(g, g.finestLevel())});
    build.push_back({"encode batches", encodeBatchBytes(g, lossy)});

    BuildMemoryEstimate e;
    e.streaming = false;
    e.terms = ingest;
    for (const std::vector<MemoryTerm>* phase : {&coarsening, &build})
        if (sumOf(*phase) > sumOf(e.terms))
            e.terms = *phase;
    return e;
}

} // namespace

uint64_t BuildMemoryEstimate::total() const
{
    return sumOf(terms);
}

std::string BuildMemoryEstimate::describe() const
{
    std::string out = streaming ? "streaming: " : "in memory: ";
    const uint64_t all = total();
    bool first = true;
    for (const MemoryTerm& t : terms) {
        if (t.bytes < all / 1000)
            continue;
        out += (first ? "" : "; ") + t.what + ", " + formatBytes(t.bytes);
        first = false;
    }
    return out;
}

bool buildStreams(const BuildOptions& options)
{
    return options.filter == PyramidFilter::Decimate && codecBuildsFinestFirst(options.codec);
}

BuildMemoryEstimate estimateBuildMemory(const io::RasterProbe& raster, const BuildOptions& options,
                                        bool streaming, bool voids)
{
    const PyramidGeometry g(raster.width, raster.height, options.patch_size);
    BuildMemoryEstimate e = streaming ? streamingEstimate(raster, g, isLossyCodec(options.codec))
                                      : inMemoryEstimate(raster, g, options, voids);
    std::stable_sort(e.terms.begin(), e.terms.end(),
                     [](const MemoryTerm& a, const MemoryTerm& b) { return a.bytes > b.bytes; });
    return e;
}

AvailableMemory buildMemoryLimit(const BuildOptions& options)
{
    if (options.memory_limit_bytes > 0)
        return {options.memory_limit_bytes, "memory_limit_bytes"};
    return availableMemory();
}

void checkBuildMemory(const std::string& input, const io::RasterProbe& raster,
                      const BuildMemoryEstimate& estimate, const AvailableMemory& limit)
{
    const uint64_t needed = estimate.total();
    if (needed <= limit.bytes)
        return;
    throw Error(input + ": " + std::to_string(raster.width) + " x " +
                std::to_string(raster.height) + " samples need about " + formatBytes(needed) +
                " to build (" + estimate.describe() + "), but " + formatBytes(limit.bytes) +
                " are available (" + limit.source + "); raise memory_limit_bytes to override");
}

} // namespace ridge
