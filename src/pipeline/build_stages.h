#pragma once
// The parts of a build that both `ridge build` (build.cpp: in memory or streamed) and the
// sharded build (shard_*.cpp) run: the context (geometry, codec, header), the metadata, one
// patch's training observation and encoding, and parallel encoding written in order.
// Internal to ridge_pipeline.
#include "ridge/archive/archive_writer.h"
#include "ridge/archive/format.h"
#include "ridge/archive/sample_flags_storage.h"
#include "ridge/archive/validity_storage.h"
#include "ridge/codec/height_codec.h"
#include "ridge/io/raster_source.h"
#include "ridge/pipeline/build.h"
#include "ridge/pyramid/level_pyramid.h"
#include "ridge/pyramid/patch_error.h"
#include "ridge/pyramid/sample_flags.h"
#include "ridge/pyramid/tessellation_block_errors.h"
#include "ridge/pyramid/validity_pyramid.h"

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace ridge::build_stages {

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

// Shared by every build path.
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

// Geometry, the (untrained) codec and the header of a width × height raster quantized by
// `q`. Throws ridge::Error for options the codec or the tessellation blocks refuse.
BuildContext makeContext(int width, int height, const HeightQuantization& q,
                         const io::GeoReference& geo, const BuildOptions& options);

// The source as the archive names it: as given, except that an absolute path keeps only its
// file name.
std::string recordedSourceName(const std::string& source_path);

// The archive's metadata JSON (docs/FORMAT.md, "Metadata").
std::string metadataJson(const std::string& source_path, const io::IngestStats& stats,
                         const io::GeoReference& geo, const BuildContext& ctx,
                         const BuildOptions& options);

// The flags of patch `at` (its level `step` finest samples apart) of a window of finest flags
// `flags` (width × rows), clamped to the window as the pyramid's padding is.
PatchSampleFlags windowPatchFlags(const uint8_t* flags, int width, int rows, int64_t step, int n,
                                  PatchId at);

// The codec's reconstruction of the parent of patch `id` (patch at.parent() of
// `parent_level`), what a decoder holds when it decodes `id`, into `out`; null when the codec
// codes `id` without its parent. Valid for codecs whose reconstruct() needs no parent (every
// codec that builds finest-first, codecBuildsFinestFirst).
const uint16_t* parentReconstruction(const BuildContext& ctx, const LevelView* parent_level,
                                     PatchId at, PatchId id, std::vector<uint16_t>& out);

// Shows `trainer` patch `at` of `level` as patch `id` would be coded: with the codec's
// reconstruction of its parent (patch at.parent() of `parent_level`) when it predicts from it.
void observePatch(const BuildContext& ctx, CodecTrainer& trainer, const LevelView& level,
                  const LevelView* parent_level, PatchId at, PatchId id);

// Replaces ctx.codec by the codec trained on every patch of `pyramid`, for codecs with
// per-archive tables (HeightCodec::trainer); each stage sees every patch.
void trainCodec(BuildContext& ctx, const LevelPyramid& pyramid);

// Extracts patch `at` of `level` (the patch's own position, or its position inside a strip
// or shard view), measures it and encodes it as patch `id`.
// `parent` is the parent's reconstruction when the codec predicts from it, else null.
// `flags`: the patch's sample flags when ctx.flags does not hold its level (a streamed
// build's finest strip, a shard's subtree), else null.
EncodedPatch encodePatch(const BuildContext& ctx, const LevelView& level, PatchId at, PatchId id,
                         const PatchSummary& summary, const uint16_t* parent = nullptr,
                         const PatchSampleFlags* flags = nullptr);

// Encodes `count` patches in parallel batches and hands them to `write` in order. `make(k)`
// encodes the k-th.
void encodeInOrder(int64_t count, const std::function<EncodedPatch(int64_t)>& make,
                   const std::function<void(int64_t, EncodedPatch&)>& write);

// `body(k)` for k in [0, count) on OpenMP's threads (dynamic schedule, `chunk` at a time);
// the first exception any call throws is rethrown here once all have finished.
void parallelFor(int64_t count, int chunk, const std::function<void(int64_t)>& body);

// The patches a top-down encoding covers, level by level in the order they are written: the
// whole pyramid's levels, or a shard's subtree.
struct LevelSpan {
    std::function<int64_t(int level)> count;
    std::function<PatchId(int level, int64_t k)> patch_at;
    // The k of a patch among its level's (the parents' level above the span: by `above`'s
    // order, see encodeTopDown).
    std::function<int64_t(PatchId)> index_of;
};

// Encodes levels [first, end) of `span` top down, each patch from its parent's reconstruction
// when the codec predicts from it (kept one level; for level `first` from `above`, level
// first − 1's reconstructions by index_of), and hands each to `write` in order. `make(p,
// parent)` encodes patch p. With `keep_last`, `above` holds level end − 1's reconstructions
// on return when the codec predicts level `end` from them.
void encodeTopDown(const BuildContext& ctx, int first, int end, const LevelSpan& span,
                   const std::function<EncodedPatch(PatchId, const uint16_t*)>& make,
                   const std::function<void(EncodedPatch&)>& write,
                   std::vector<std::vector<uint16_t>>& above, bool keep_last = false);

// Encodes and writes every patch of levels [0, last_level] of `pyramid` top down, with the
// bounds in `errors` (the in-memory build's levels, a streamed build's levels above the finest).
void writeLevels(const BuildContext& ctx, const LevelPyramid& pyramid, int last_level,
                 const PatchErrors& errors, archive::ArchiveWriter& writer,
                 const Progress& progress);

} // namespace ridge::build_stages
