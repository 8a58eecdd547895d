// The build's shared stages (build_stages.h).
#include "build_stages.h"

#include "ridge/archive/block_error_storage.h"
#include "ridge/core/error.h"
#include "ridge/core/json_text.h"
#include "ridge/pipeline/build_memory.h"
#include "ridge/pyramid/patch_context.h"
#include "ridge/pyramid/patch_error.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <filesystem>
#include <nlohmann/json.hpp>

namespace ridge::build_stages {

namespace {

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

} // namespace

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

PatchSampleFlags windowPatchFlags(const uint8_t* flags, int width, int rows, int64_t step, int n,
                                  PatchId at)
{
    PatchSampleFlags out{PatchSampleFlags::Kind::Mixed, n, std::vector<uint8_t>(size_t(n) * n)};
    const int64_t c = n - 1;
    for (int j = 0; j < n; ++j) {
        const int64_t y = std::min<int64_t>((at.y * c + j) * step, rows - 1);
        const uint8_t* row = flags + static_cast<size_t>(y) * width;
        for (int i = 0; i < n; ++i)
            out.flags[static_cast<size_t>(j) * n + i] =
                row[std::min<int64_t>((at.x * c + i) * step, width - 1)];
    }
    out.canonicalize();
    return out;
}

const uint16_t* parentReconstruction(const BuildContext& ctx, const LevelView* parent_level,
                                     PatchId at, PatchId id, std::vector<uint16_t>& out)
{
    if (!ctx.codec->needsParent(id.level))
        return nullptr;
    if (!parent_level)
        throw Error("internal error: a patch coded without its parent's level");
    const PyramidGeometry& g = ctx.geometry;
    const int n = g.patchSize();
    thread_local std::vector<uint16_t> parent_codes;
    parent_codes.resize(static_cast<size_t>(n) * n);
    out.resize(parent_codes.size());
    extractPatch(*parent_level, n, at.parent(), parent_codes.data());
    ctx.codec->reconstruct(parent_codes.data(), patchContext(g, id.parent(), nullptr), out.data());
    return out.data();
}

void observePatch(const BuildContext& ctx, CodecTrainer& trainer, const LevelView& level,
                  const LevelView* parent_level, PatchId at, PatchId id)
{
    const PyramidGeometry& g = ctx.geometry;
    const int n = g.patchSize();
    thread_local std::vector<uint16_t> codes, parent;
    codes.resize(static_cast<size_t>(n) * n);
    extractPatch(level, n, at, codes.data());
    const uint16_t* parent_ptr = parentReconstruction(ctx, parent_level, at, id, parent);
    trainer.observe(codes.data(), patchContext(g, id, parent_ptr));
}

namespace {

void trainStage(BuildContext& ctx, const LevelPyramid& pyramid, CodecTrainer& trainer)
{
    const PyramidGeometry& g = ctx.geometry;
    parallelFor(g.patchCount(), 4, [&](int64_t index) {
        const PatchId p = g.patchAt(index);
        observePatch(ctx, trainer, pyramid.level(p.level),
                     p.level > 0 ? &pyramid.level(p.level - 1) : nullptr, p, p);
    });
    ctx.codec = trainer.finish();
}

} // namespace

void trainCodec(BuildContext& ctx, const LevelPyramid& pyramid)
{
    // A codec may learn in stages (progressive v2: predictor corrections, then the tables
    // coded with them); each stage sees every patch.
    while (std::unique_ptr<CodecTrainer> trainer = ctx.codec->trainer())
        trainStage(ctx, pyramid, *trainer);
}

EncodedPatch encodePatch(const BuildContext& ctx, const LevelView& level, PatchId at, PatchId id,
                         const PatchSummary& summary, const uint16_t* parent,
                         const PatchSampleFlags* flags)
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

void parallelFor(int64_t count, int chunk, const std::function<void(int64_t)>& body)
{
    std::exception_ptr failure;
#pragma omp parallel for schedule(dynamic, chunk)
    for (int64_t k = 0; k < count; ++k) {
        try {
            body(k);
        } catch (...) {
#pragma omp critical
            if (!failure)
                failure = std::current_exception();
        }
    }
    if (failure)
        std::rethrow_exception(failure);
}

void encodeInOrder(int64_t count, const std::function<EncodedPatch(int64_t)>& make,
                   const std::function<void(int64_t, EncodedPatch&)>& write)
{
    constexpr int64_t kBatch = kEncodeBatchPatches;
    std::vector<EncodedPatch> batch(static_cast<size_t>(std::min(kBatch, count)));
    for (int64_t first = 0; first < count; first += kBatch) {
        const int64_t n = std::min(kBatch, count - first);
        parallelFor(n, 1, [&](int64_t k) { batch[size_t(k)] = make(first + k); });
        for (int64_t k = 0; k < n; ++k)
            write(first + k, batch[size_t(k)]);
    }
}

void encodeTopDown(const BuildContext& ctx, int first, int end, const LevelSpan& span,
                   const std::function<EncodedPatch(PatchId, const uint16_t*)>& make,
                   const std::function<void(EncodedPatch&)>& write,
                   std::vector<std::vector<uint16_t>>& above, bool keep_last)
{
    // The children of level l are all of level l + 1: a reconstruction is kept one level.
    std::vector<std::vector<uint16_t>> current;
    for (int level = first; level < end; ++level) {
        const bool keep = ctx.codec->needsParent(level + 1) && (level + 1 < end || keep_last);
        current.assign(keep ? size_t(span.count(level)) : 0, {});
        encodeInOrder(
            span.count(level),
            [&](int64_t k) {
                const PatchId p = span.patch_at(level, k);
                const uint16_t* parent = nullptr;
                if (ctx.codec->needsParent(level))
                    parent = above[size_t(span.index_of(p.parent()))].data();
                return make(p, parent);
            },
            [&](int64_t k, EncodedPatch& e) {
                write(e);
                if (keep)
                    current[size_t(k)] = std::move(e.reconstruction);
            });
        above.swap(current);
    }
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

} // namespace ridge::build_stages
