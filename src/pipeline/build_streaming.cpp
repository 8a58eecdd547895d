// The decimation build without ever holding the finest grid (docs/DESIGN.md, "Build
// pipeline").
//
// The finest level is read in strips of two patch rows (2C+1 sample rows; the row two strips
// share is read twice, 1/2C extra). Each strip's even samples fill the materialised level L−1
// (a quarter of the data), against which level L−1's Err_Int is measured, and its finest
// patches are encoded and written at once. Levels 0..L−1 are then built in memory from level
// L−1 exactly as the in-memory path would build them.
//
// A codec that learns per-archive tables (the progressive codec: predictor corrections, then
// entropy tables coded with them) must see every patch before it encodes one. Its build reads
// the strips once per training stage instead of holding them: the first pass also fills level
// L−1, every pass shows the trainer the strips' finest patches and then levels 0..L−1 from
// memory, and a last pass encodes. Memory stays that of the lossless build; the price is one
// more read of the source per stage. A finest patch is coded from its parent's
// reconstruction, which such a codec makes from the parent's codes alone (level L−1 holds
// them), and the trainer's sums are exact, so the codec and every payload equal the in-memory
// build's.
#include "build_streaming.h"

#include "build_stages.h"

#include "ridge/archive/archive_writer.h"
#include "ridge/codec/height_codec.h"
#include "ridge/core/error.h"
#include "ridge/pyramid/patch_context.h"
#include "ridge/pyramid/patch_error.h"
#include "ridge/pyramid/sample_flags.h"

#include <algorithm>
#include <chrono>

namespace ridge {

namespace {

using namespace build_stages;

// Finest-level strip k: source rows [2kC, 2kC + 2C], fewer at the bottom edge, and their
// water flags when the build has any.
class FinestStrips {
  public:
    FinestStrips(io::CodeRowReader& source, const PyramidGeometry& g, bool water)
        : source_(source), g_(g), codes_(static_cast<size_t>(2 * g.cells() + 1) * g.width()),
          flags_(water ? codes_.size() : 0)
    {
    }
    int count() const { return g_.patchesY(g_.finestLevel() - 1); }
    // Reads strip k; false when it holds a void (filling one needs the whole grid).
    bool read(int k)
    {
        first_row_ = 2 * k * g_.cells();
        rows_ = std::min(2 * g_.cells() + 1, g_.height() - first_row_);
        return source_.readRows(first_row_, rows_, codes_.data(),
                                flags_.empty() ? nullptr : flags_.data()) == 0;
    }
    LevelView view() const { return {codes_.data(), g_.width(), rows_, 1, g_.width(), rows_}; }
    int firstRow() const { return first_row_; }
    int rows() const { return rows_; }
    // Strip row of level L−1's row j (2j, clamped to the strip).
    size_t rowOffset(int j) const
    {
        return static_cast<size_t>(std::min(2 * j - first_row_, rows_ - 1)) * g_.width();
    }
    const uint16_t* codes() const { return codes_.data(); }
    const uint8_t* flags() const { return flags_.empty() ? nullptr : flags_.data(); }

  private:
    io::CodeRowReader& source_;
    const PyramidGeometry& g_;
    std::vector<uint16_t> codes_;
    std::vector<uint8_t> flags_;
    int first_row_ = 0;
    int rows_ = 0;
};

class StreamingBuild {
  public:
    StreamingBuild(const std::string& input, const BuildOptions& options)
        : input_(input), options_(options), source_(input, options.ingest),
          ctx_(makeContext(source_.width(), source_.height(), source_.quantization(), source_.geo(),
                           options)),
          g_(ctx_.geometry), finest_(g_.finestLevel()), water_(source_.flagsWater())
    {
    }

    std::optional<BuildReport> run(const std::string& output);

  private:
    // Pass 1: reads every strip, fills level L−1 and its Err_Int, and shows `trainer` the
    // finest patches (or, with nothing to learn, encodes and writes them). False on a void.
    bool firstPass(CodecTrainer* trainer, archive::ArchiveWriter& writer, const Progress& progress);
    // Reads every strip again for `trainer`, or to encode and write when it is null.
    void laterPass(CodecTrainer* trainer, archive::ArchiveWriter* writer, const Progress& progress);
    // Level L−1's rows [kC, kC + C] from strip k's even samples (clamped at the edges).
    void fillCoarseRows(const FinestStrips& strip, int k);
    // Throws when strip k's even samples are no longer level L−1's: the source changed
    // between two passes.
    void checkCoarseRows(const FinestStrips& strip, int k) const;
    // Level L−1's patch row k (rows [kC, kC + C]): the parents of strip k's finest patches.
    LevelView coarseRow(int k) const;
    void observeStrip(const FinestStrips& strip, int k, CodecTrainer& trainer) const;
    void encodeStrip(const FinestStrips& strip, int k, archive::ArchiveWriter& writer);

    const std::string& input_;
    const BuildOptions& options_;
    io::CodeRowReader source_;
    BuildContext ctx_;
    const PyramidGeometry& g_;
    const int finest_;
    const bool water_;
    PatchErrors errors_ = makePatchErrors(g_);
    CodeGrid coarse_; // level L−1, materialised
    // Water (a sea level or a water layer): level L−1's flags, whose samples are the finest
    // at even positions, from which every coarser level's flags follow.
    SampleFlagsGrid coarse_flags_;
};

void StreamingBuild::fillCoarseRows(const FinestStrips& strip, int k)
{
    const int cells = g_.cells(), width = g_.width();
    const int j_end = std::min(k * cells + cells, coarse_.height - 1);
    for (int j = k * cells; j <= j_end; ++j) {
        const size_t from = strip.rowOffset(j);
        const uint16_t* src = strip.codes() + from;
        uint16_t* dst = coarse_.codes.data() + static_cast<size_t>(j) * coarse_.width;
        for (int i = 0; i < coarse_.width; ++i)
            dst[i] = src[std::min(2 * i, width - 1)];
        if (water_) {
            const uint8_t* fsrc = strip.flags() + from;
            for (int i = 0; i < coarse_.width; ++i)
                coarse_flags_.set(i, j, fsrc[std::min(2 * i, width - 1)]);
        }
    }
}

void StreamingBuild::checkCoarseRows(const FinestStrips& strip, int k) const
{
    const int cells = g_.cells(), width = g_.width();
    const int j_end = std::min(k * cells + cells, coarse_.height - 1);
    for (int j = k * cells; j <= j_end; ++j) {
        const uint16_t* src = strip.codes() + strip.rowOffset(j);
        const uint16_t* row = coarse_.codes.data() + static_cast<size_t>(j) * coarse_.width;
        for (int i = 0; i < coarse_.width; ++i)
            if (row[i] != src[std::min(2 * i, width - 1)])
                throw Error(input_ + ": changed while it was being built (row " +
                            std::to_string(2 * j) + " reads differently on a second pass)");
    }
}

LevelView StreamingBuild::coarseRow(int k) const
{
    const int cells = g_.cells();
    const int rows = std::min(k * cells + cells, coarse_.height - 1) - k * cells + 1;
    return {coarse_.codes.data() + static_cast<size_t>(k) * cells * coarse_.width,
            coarse_.width,
            rows,
            1,
            coarse_.width,
            rows};
}

void StreamingBuild::observeStrip(const FinestStrips& strip, int k, CodecTrainer& trainer) const
{
    const LevelView view = strip.view(), parents = coarseRow(k);
    const int across = g_.patchesX(finest_);
    const int halves = std::min(2, g_.patchesY(finest_) - 2 * k);
    parallelFor(int64_t(halves) * across, 4, [&](int64_t index) {
        const int half = int(index / across), x = int(index % across);
        observePatch(ctx_, trainer, view, &parents, {finest_, x, half}, {finest_, x, 2 * k + half});
    });
}

void StreamingBuild::encodeStrip(const FinestStrips& strip, int k, archive::ArchiveWriter& writer)
{
    const LevelView view = strip.view(), parents = coarseRow(k);
    const int n = g_.patchSize();
    for (int half = 0; half < 2 && 2 * k + half < g_.patchesY(finest_); ++half) {
        const int py = 2 * k + half;
        encodeInOrder(
            g_.patchesX(finest_),
            [&](int64_t x) {
                const PatchId at{finest_, int(x), half}, id{finest_, int(x), py};
                PatchSampleFlags flags{PatchSampleFlags::Kind::None, n, {}};
                if (water_)
                    flags = windowPatchFlags(strip.flags(), g_.width(), strip.rows(), 1, n, at);
                thread_local std::vector<uint16_t> parent;
                return encodePatch(ctx_, view, at, id, {},
                                   parentReconstruction(ctx_, &parents, at, id, parent), &flags);
            },
            [&](int64_t x, EncodedPatch& e) {
                writer.writePatch(e.record, e.block_errors, e.validity, e.sample_flags,
                                  e.payload.data(), e.payload.size());
                const int64_t index = g_.patchIndex({finest_, int(x), py});
                errors_.min_code[index] = e.own_min;
                errors_.max_code[index] = e.own_max;
            });
    }
}

bool StreamingBuild::firstPass(CodecTrainer* trainer, archive::ArchiveWriter& writer,
                               const Progress& progress)
{
    FinestStrips strip(source_, g_, water_);
    const int n = g_.patchSize();
    for (int k = 0; k < strip.count(); ++k) {
        if (!strip.read(k))
            return false;
        // Level L−1 first: the strip's finest patches are coded from it.
        fillCoarseRows(strip, k);
        if (trainer)
            observeStrip(strip, k, *trainer);
        else
            encodeStrip(strip, k, writer);
        // Err_Int of level L−1's patch row k, against the strip.
        const LevelView parents = coarseRow(k), view = strip.view();
        parallelFor(g_.patchesX(finest_ - 1), 1, [&](int64_t x) {
            errors_.err_int[g_.patchIndex({finest_ - 1, int(x), k})] =
                static_cast<float>(interpolationError(parents, view, n, {finest_ - 1, int(x), 0}));
        });
        reportProgress(progress, double(k + 1) / strip.count());
    }
    return true;
}

void StreamingBuild::laterPass(CodecTrainer* trainer, archive::ArchiveWriter* writer,
                               const Progress& progress)
{
    FinestStrips strip(source_, g_, water_);
    for (int k = 0; k < strip.count(); ++k) {
        if (!strip.read(k))
            throw Error(input_ + ": changed while it was being built (a void appeared in rows " +
                        std::to_string(strip.firstRow()) + " and on)");
        checkCoarseRows(strip, k);
        if (trainer)
            observeStrip(strip, k, *trainer);
        else
            encodeStrip(strip, k, *writer);
        reportProgress(progress, double(k + 1) / strip.count());
    }
}

std::optional<BuildReport> StreamingBuild::run(const std::string& output)
{
    const auto start = std::chrono::steady_clock::now();
    if (finest_ == 0)
        return std::nullopt;
    archive::ArchiveWriter writer(output, ctx_.header);
    coarse_.width = g_.levelWidth(finest_ - 1);
    coarse_.height = g_.levelHeight(finest_ - 1);
    coarse_.codes.resize(static_cast<size_t>(coarse_.width) * coarse_.height);
    if (water_)
        coarse_flags_ = SampleFlagsGrid(coarse_.width, coarse_.height);

    // Progress: the strip passes take [0, 0.8), each later one half of what is left.
    double done = 0.0, slice = 0.8;
    std::unique_ptr<CodecTrainer> trainer = ctx_.codec->trainer();
    const bool trains = trainer != nullptr;
    if (trains)
        slice /= 2;
    if (!firstPass(trainer.get(), writer, subProgress(options_.progress, done, done + slice)))
        return std::nullopt;
    done += slice;

    // Levels 0..L−1 from the materialised level L−1: same views, same patch indices.
    const LevelPyramid pyramid(coarse_,
                               PyramidGeometry(coarse_.width, coarse_.height, g_.patchSize()),
                               PyramidFilter::Decimate);
    if (pyramid.geometry().levelCount() != finest_)
        throw Error("internal error: level L-1 geometry mismatch");
    measurePatches(pyramid, 0, finest_ - 1, errors_);

    // Each training stage sees every patch: the finest in a pass over the strips (the first
    // stage's was pass 1), then levels 0..L−1 from memory.
    for (bool first = true; trainer; first = false) {
        if (!first) {
            slice /= 2;
            laterPass(trainer.get(), nullptr, subProgress(options_.progress, done, done + slice));
            done += slice;
        }
        parallelFor(g_.firstPatchIndex(finest_), 4, [&](int64_t index) {
            const PatchId p = g_.patchAt(index);
            observePatch(ctx_, *trainer, pyramid.level(p.level),
                         p.level > 0 ? &pyramid.level(p.level - 1) : nullptr, p, p);
        });
        ctx_.codec = trainer->finish();
        trainer = ctx_.codec->trainer();
    }
    if (trains) {
        writer.setCodecTables(ctx_.codec->storeTables());
        laterPass(nullptr, &writer, subProgress(options_.progress, done, 0.8));
    }

    accumulatePatchErrors(g_, finest_, errors_);
    if (water_)
        ctx_.flags =
            std::make_unique<SampleFlagsPyramid>(std::move(coarse_flags_), finest_ - 1, g_);
    writeLevels(ctx_, pyramid, finest_ - 1, errors_, writer,
                subProgress(options_.progress, 0.8, 1.0));
    writer.finish(metadataJson(input_, source_.stats(), source_.geo(), ctx_, options_));
    reportDone(options_.progress); // published: too late to cancel

    BuildReport report;
    report.width = g_.width();
    report.height = g_.height();
    report.level_count = g_.levelCount();
    report.patch_count = g_.patchCount();
    report.archive_bytes = writer.bytesWritten();
    report.quantization_error = ctx_.header.quantization_error;
    report.streamed = true;
    report.seconds_total =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return report;
}

} // namespace

std::optional<BuildReport> buildStreaming(const std::string& input, const std::string& output,
                                          const BuildOptions& options)
{
    return StreamingBuild(input, options).run(output);
}

} // namespace ridge
