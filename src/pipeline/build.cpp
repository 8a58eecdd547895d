#include "ridge/pipeline/build.h"

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

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start)
{
    return std::chrono::duration<double>(Clock::now() - start).count();
}

// What the index needs about a patch beyond its samples. min/max start "empty" so that
// encodePatch's own range decides unless descendants widened it.
struct PatchSummary {
    uint16_t min_code = 0xffff;
    uint16_t max_code = 0;
    float err_appr = 0.f; // code units
};

// Everything the writer needs for one patch, produced in parallel and written in order.
struct EncodedPatch {
    archive::PatchRecord record;
    std::vector<uint8_t> block_errors;
    std::vector<uint8_t> validity = archive::allValidMask();
    std::vector<uint8_t> sample_flags = archive::noSampleFlags();
    std::vector<uint8_t> payload;
    std::vector<uint16_t> reconstruction; // kept only when children predict from it
    uint16_t own_min = 0;
    uint16_t own_max = 0;
};

// Shared by both build paths.
struct BuildContext {
    PyramidGeometry geometry;
    TessellationBlockLayout layout;
    std::unique_ptr<HeightCodec> codec;
    archive::Header header;
    bool store_block_errors = false;
    // Kept nodata (io::VoidFill): the per-patch masks; null when every sample is data.
    std::unique_ptr<ValidityPyramid> validity;
    // Water and filled samples (pyramid/sample_flags.h); null when no sample has a flag.
    std::unique_ptr<SampleFlagsPyramid> flags;

    double levelBound(int level) const
    {
        return codec->levelErrorBound(level) * header.height_scale + header.quantization_error;
    }
};

// The finest-level bound of a lossy codec in codes: what --max-error leaves after the
// ingest quantization, so that the bound in metres holds end to end.
double codecMaxError(const HeightQuantization& q, const BuildOptions& options)
{
    if (!isLossyCodec(options.codec))
        return 0;
    if (!options.max_error)
        throw Error("codec '" + options.codec + "' needs max_error (metres)");
    if (!(*options.max_error >= q.max_error)) // max_error > 0: BuildOptions::validate
        throw Error("max_error " + std::to_string(*options.max_error) +
                    " m is below the input's own quantization error " +
                    std::to_string(q.max_error) + " m");
    return std::min(32767.0, (*options.max_error - q.max_error) / q.scale);
}

BuildContext makeContext(int width, int height, const HeightQuantization& q,
                         const io::GeoReference& geo, const BuildOptions& options)
{
    BuildContext ctx{PyramidGeometry(width, height, options.patch_size),
                     TessellationBlockLayout{options.patch_size, options.block_cells},
                     nullptr,
                     {},
                     false,
                     nullptr,
                     nullptr};
    if (!ctx.layout.valid())
        throw Error("block size " + std::to_string(options.block_cells) +
                    " cells must be a power of two >= 2 dividing the patch's " +
                    std::to_string(options.patch_size - 1) + " cells");
    ctx.codec = makeCodec(options.codec, codecMaxError(q, options), ctx.geometry.levelCount());
    // Err(P), the selection and the skirts rest on a bound: a codec mode without one (the
    // fractal paper's) is for codec-bench, not for archives.
    if (!std::isfinite(ctx.codec->levelErrorBound(ctx.geometry.finestLevel())))
        throw Error("codec '" + options.codec +
                    "' bounds no error (the paper's mode): an archive needs a bound for Err(P); "
                    "ridge codec-bench --ridge-codec '" +
                    options.codec + "' measures it");
    ctx.store_block_errors = options.store_block_errors;
    archive::Header& h = ctx.header;
    h.width = static_cast<uint32_t>(width);
    h.height = static_cast<uint32_t>(height);
    h.patch_size = static_cast<uint32_t>(options.patch_size);
    h.level_count = static_cast<uint32_t>(ctx.geometry.levelCount());
    h.block_cells = static_cast<uint32_t>(ctx.layout.block_cells);
    h.block_levels = static_cast<uint32_t>(ctx.layout.levels());
    h.codec_id = static_cast<uint32_t>(ctx.codec->id());
    h.filter_id = static_cast<uint32_t>(options.filter);
    h.height_scale = q.scale;
    h.height_offset = q.offset;
    h.spacing_x = geo.spacing_x;
    h.spacing_y = geo.spacing_y;
    h.quantization_error = q.max_error;
    ctx.codec->storeParameters(h.codec_param);
    return ctx;
}

// The source as the archive names it: as given, except that an absolute path keeps only its
// file name (an archive travels; the builder's directories are none of its readers' business).
std::string recordedSourceName(const std::string& source_path)
{
    const std::filesystem::path p(source_path);
    return p.is_absolute() && p.has_filename() ? p.filename().string() : source_path;
}

std::string metadataJson(const std::string& source_path, const io::IngestStats& stats,
                         const io::GeoReference& geo, const BuildContext& ctx,
                         const BuildOptions& options)
{
    nlohmann::json meta = {
        {"generator", "ridge 0.1.0"},
        {"source",
         {{"path", recordedSourceName(source_path)},
          {"data_type", stats.data_type},
          {"band", options.ingest.band},
          {"width", ctx.geometry.width()},
          {"height", ctx.geometry.height()},
          {"valid_samples", stats.valid_samples},
          {"voids_filled", stats.voids_filled},
          {"voids_kept", stats.voids_kept},
          {"fill_voids", io::voidFillName(options.ingest.fill_voids)},
          {"void_fill", "GDALFillNodata (inverse distance weighting, 2 smoothing passes)"},
          {"min_metres", stats.min_metres},
          {"max_metres", stats.max_metres},
          {"exact", stats.exact}}},
        {"georeference",
         {{"crs_wkt", geo.crs_wkt},
          {"geographic", geo.geographic},
          {"vertical_units", geo.vertical_units},
          {"spacing_from_user", geo.spacing_from_user}}},
        {"build",
         {{"patch_size", options.patch_size},
          {"block_cells", options.block_cells},
          {"codec", options.codec},
          {"block_errors", options.store_block_errors ? "stored" : "derived from decoded heights"},
          {"filter", filterName(options.filter)},
          {"z_scale", stats.z_scale},
          {"z_offset", stats.z_offset}}},
    };
    if (geo.has_geotransform)
        meta["georeference"]["geotransform"] = geo.geotransform;
    if (geo.vertical_datum.known()) {
        nlohmann::json& datum = meta["georeference"]["vertical_datum"];
        datum = {{"name", geo.vertical_datum.name}, {"from", geo.vertical_datum.origin}};
        if (geo.vertical_datum.epsg)
            datum["epsg"] = *geo.vertical_datum.epsg;
    }
    if (geo.vertical_shift) {
        const io::VerticalDatum& from = geo.vertical_shift->from;
        meta["build"]["vertical_shift"] = {{"from", from.name},
                                           {"from_epsg", from.epsg.value_or(0)},
                                           {"operation", geo.vertical_shift->operation}};
    }
    // JSON has no NaN: a NaN nodata (float rasters) is recorded as absent, and extract then
    // writes NaN anyway.
    if (stats.nodata && std::isfinite(*stats.nodata))
        meta["source"]["nodata"] = *stats.nodata;
    if (options.ingest.max_error)
        meta["build"]["max_error"] = *options.ingest.max_error;
    if (options.max_error)
        meta["build"]["codec_max_error"] = *options.max_error;
    nlohmann::json water = {{"sea_level", nullptr}, {"samples", stats.water_samples}};
    if (options.ingest.sea_level)
        water["sea_level"] = *options.ingest.sea_level;
    if (!options.ingest.water_layer.empty())
        water["layer"] = options.ingest.water_layer;
    meta["water"] = water;
    if (const std::string variant = ctx.codec->variantDescription(); !variant.empty())
        meta["build"]["codec_variant"] = variant;
    return jsonText(meta); // any bytes in source.path: invalid UTF-8 becomes U+FFFD
}

void trainStage(BuildContext& ctx, const LevelPyramid& pyramid, CodecTrainer& trainer);

// The flags of finest patch (x, half) of a streamed strip: `flags` holds the strip's `rows`
// finest rows of `width` samples; positions clamp to the extent as the pyramid's padding
// does (a strip's last row is the raster's last only in the last strip, where it is needed).
PatchSampleFlags stripPatchFlags(const uint8_t* flags, int width, int rows, int n, int x, int half)
{
    PatchSampleFlags out{PatchSampleFlags::Kind::Mixed, n, std::vector<uint8_t>(size_t(n) * n)};
    const int c = n - 1;
    for (int j = 0; j < n; ++j) {
        const uint8_t* row = flags + static_cast<size_t>(std::min(half * c + j, rows - 1)) * width;
        for (int i = 0; i < n; ++i)
            out.flags[static_cast<size_t>(j) * n + i] = row[std::min(x * c + i, width - 1)];
    }
    out.canonicalize();
    return out;
}

// Replaces ctx.codec by the codec trained on every patch of `pyramid`, for codecs with
// per-archive tables (HeightCodec::trainer); each patch is shown exactly what encodePatch
// will code, the parent's reconstruction included.
void trainCodec(BuildContext& ctx, const LevelPyramid& pyramid)
{
    // A codec may learn in stages (progressive v2: predictor corrections, then the tables
    // coded with them); each stage sees every patch.
    while (std::unique_ptr<CodecTrainer> trainer = ctx.codec->trainer())
        trainStage(ctx, pyramid, *trainer);
}

void trainStage(BuildContext& ctx, const LevelPyramid& pyramid, CodecTrainer& trainer)
{
    const PyramidGeometry& g = ctx.geometry;
    const int n = g.patchSize();
    const int64_t count = g.patchCount();
    std::exception_ptr failure;
#pragma omp parallel for schedule(dynamic, 4)
    for (int64_t index = 0; index < count; ++index) {
        try {
            thread_local std::vector<uint16_t> codes, parent_codes, parent;
            codes.resize(static_cast<size_t>(n) * n);
            const PatchId p = g.patchAt(index);
            extractPatch(pyramid.level(p.level), n, p, codes.data());
            const uint16_t* parent_ptr = nullptr;
            if (ctx.codec->needsParent(p.level)) {
                const PatchId up = p.parent();
                parent_codes.resize(codes.size());
                parent.resize(codes.size());
                extractPatch(pyramid.level(up.level), n, up, parent_codes.data());
                ctx.codec->reconstruct(parent_codes.data(), patchContext(g, up, nullptr),
                                       parent.data());
                parent_ptr = parent.data();
            }
            trainer.observe(codes.data(), patchContext(g, p, parent_ptr));
        } catch (...) {
#pragma omp critical
            failure = std::current_exception();
        }
    }
    if (failure)
        std::rethrow_exception(failure);
    ctx.codec = trainer.finish();
}

// Extracts patch `at` of `level` (the patch's own position, or its position inside a strip
// view), measures it and encodes it as patch `id`.
// `parent` is the parent's reconstruction when the codec predicts from it, else null.
// `flags`: the patch's sample flags when ctx.flags does not hold its level (a streamed
// build's finest strip), else null.
EncodedPatch encodePatch(const BuildContext& ctx, const LevelView& level, PatchId at, PatchId id,
                         const PatchSummary& summary, const uint16_t* parent = nullptr,
                         const PatchSampleFlags* flags = nullptr)
{
    const int n = ctx.geometry.patchSize();
    thread_local std::vector<uint16_t> codes;
    thread_local std::vector<float> lambda;
    codes.resize(static_cast<size_t>(n) * n);
    lambda.resize(ctx.layout.valuesPerPatch());
    extractPatch(level, n, at, codes.data());
    const PatchContext pctx = patchContext(ctx.geometry, id, parent);

    EncodedPatch out;
    const auto [lo, hi] = std::minmax_element(codes.begin(), codes.end());
    out.own_min = *lo;
    out.own_max = *hi;
    // min/max must hold what is drawn: the reconstructions of the patch and its descendants
    // lie within δ_l of the exact heights (descendants' δ are smaller).
    const int delta = static_cast<int>(ctx.codec->levelErrorBound(id.level));
    const int min_code = std::max(0, int(std::min(*lo, summary.min_code)) - delta);
    const int max_code = std::min(65535, int(std::max(*hi, summary.max_code)) + delta);
    const archive::Header& h = ctx.header;
    out.record.level = static_cast<uint32_t>(id.level);
    out.record.x = static_cast<uint32_t>(id.x);
    out.record.y = static_cast<uint32_t>(id.y);
    out.record.min_height = archive::floatDown(h.height_offset + h.height_scale * min_code);
    out.record.max_height = archive::floatUp(h.height_offset + h.height_scale * max_code);
    const double err_appr = summary.err_appr * h.height_scale;
    out.record.err_appr = archive::floatUp(err_appr);
    out.record.err = archive::floatUp(err_appr + ctx.levelBound(id.level));

    out.payload.resize(ctx.codec->encodeBound(pctx));
    const size_t size =
        ctx.codec->encode(out.payload.data(), out.payload.size(), codes.data(), pctx);
    if (size == 0)
        throw Error("internal error: cannot encode patch");
    out.payload.resize(size);

    // λ is measured on what the renderer will draw: the codec's reconstruction, decoded from
    // the payload just written (a codec whose encoder searches, like jpeg2000's rate
    // control, would otherwise search twice; and the payload is proven to decode).
    const uint16_t* drawn = codes.data();
    if (!ctx.codec->lossless()) {
        out.reconstruction.resize(codes.size());
        const int status = ctx.codec->decode(out.reconstruction.data(), out.payload.data(),
                                             out.payload.size(), pctx);
        if (status == kCodecDisabled) // the user's to fix, not ours: say how
            throw Error(std::string("the build decodes every patch it encodes, but ") +
                        codecStatusMessage(status));
        if (status != kCodecOk)
            throw Error(std::string("internal error: a patch just encoded does not decode: ") +
                        codecStatusMessage(status));
        drawn = out.reconstruction.data();
    }
    if (ctx.store_block_errors) {
        computeTessellationBlockErrors(drawn, ctx.layout, lambda.data());
        out.block_errors = archive::packBlockErrors(lambda.data(), lambda.size(), h.height_scale);
        if (out.block_errors.empty())
            throw Error("internal error: cannot pack block errors");
    }

    if (ctx.validity) {
        out.validity = archive::packValidity(ctx.validity->patch(id), n);
        if (out.validity.empty())
            throw Error("internal error: cannot pack a validity mask");
    }
    if (flags || ctx.flags) {
        out.sample_flags = archive::packSampleFlags(flags ? *flags : ctx.flags->patch(id), n);
        if (out.sample_flags.empty())
            throw Error("internal error: cannot pack sample flags");
    }

    return out;
}

// Encodes `count` patches in parallel batches and writes them in order. `make(k)` encodes
// the k-th; `done(k, patch)` sees each after it was written (for bookkeeping).
void encodeAndWrite(int64_t count, const std::function<EncodedPatch(int64_t)>& make,
                    archive::ArchiveWriter& writer,
                    const std::function<void(int64_t, EncodedPatch&)>& done = {})
{
    constexpr int64_t kBatch = kEncodeBatchPatches;
    std::vector<EncodedPatch> batch(kBatch);
    for (int64_t first = 0; first < count; first += kBatch) {
        const int64_t n = std::min(kBatch, count - first);
        std::exception_ptr failure;
#pragma omp parallel for schedule(dynamic, 1)
        for (int64_t k = 0; k < n; ++k) {
            try {
                batch[k] = make(first + k);
            } catch (...) {
#pragma omp critical
                failure = std::current_exception();
            }
        }
        if (failure)
            std::rethrow_exception(failure);
        for (int64_t k = 0; k < n; ++k) {
            writer.writePatch(batch[k].record, batch[k].block_errors, batch[k].validity,
                              batch[k].sample_flags, batch[k].payload.data(),
                              batch[k].payload.size());
            if (done)
                done(first + k, batch[k]);
        }
    }
}

// Writes every patch of levels [0, last_level] from `pyramid` with the bounds in `errors`.
void writeLevels(const BuildContext& ctx, const LevelPyramid& pyramid, int last_level,
                 const PatchErrors& errors, archive::ArchiveWriter& writer,
                 const Progress& progress)
{
    // Level by level, top-down: a progressive codec codes each patch from its parent's
    // reconstruction, kept for one level (the children of level l are all of level l+1).
    const PyramidGeometry& g = ctx.geometry;
    const int64_t count = g.firstPatchIndex(last_level) + g.patchCount(last_level);
    std::vector<std::vector<uint16_t>> parents, current;
    for (int level = 0; level <= last_level; ++level) {
        const int64_t first = g.firstPatchIndex(level);
        const bool keep = ctx.codec->needsParent(level + 1) && level < last_level;
        current.assign(keep ? static_cast<size_t>(g.patchCount(level)) : 0, {});
        encodeAndWrite(
            g.patchCount(level),
            [&](int64_t k) {
                const int64_t index = first + k;
                const PatchId p = g.patchAt(index);
                const PatchSummary summary{errors.min_code[index], errors.max_code[index],
                                           errors.err_appr[index]};
                const uint16_t* parent = nullptr;
                if (ctx.codec->needsParent(level))
                    parent =
                        parents[g.patchIndex(p.parent()) - g.firstPatchIndex(level - 1)].data();
                EncodedPatch e = encodePatch(ctx, pyramid.level(level), p, p, summary, parent);
                if (index % 64 == 63)
                    reportProgress(progress, double(index + 1) / double(count));
                return e;
            },
            writer,
            [&](int64_t k, EncodedPatch& e) {
                if (keep)
                    current[k] = std::move(e.reconstruction);
            });
        parents.swap(current);
    }
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
                        flags = stripPatchFlags(strip_flags.data(), width, rows, n, int(x), half);
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
