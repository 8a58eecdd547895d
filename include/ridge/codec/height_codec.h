#pragma once
// Codec interface of the .ridge archive: one patch of 16-bit codes <-> one payload.
//
// API shape after meshoptimizer: the caller owns every buffer; encode returns the bytes
// written (0 = not enough room); decode returns 0 or a negative CodecStatus. Payload bytes
// are untrusted: decode checks every bound and never reads or writes outside its buffers.
//
// A codec may predict a patch from its parent's reconstruction (the progressive codec of
// the hardware-tessellation paper); PatchContext carries it. Codecs that do not need it
// ignore it. Decoding is a pure function of (context, payload).
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace ridge {

// A codec's number in the archive header (codec_id). Each codec's module names its own
// (ridge/codec/codec_registry.h registers it); nothing else knows the numbers.
enum class CodecId : uint32_t {};

enum CodecStatus : int {
    kCodecOk = 0,
    kCodecBadHeader = -1,     // magic/version/parameters do not match
    kCodecTruncated = -2,     // payload ends early
    kCodecCorrupt = -3,       // inconsistent content (entropy stream, sizes)
    kCodecTrailingBytes = -4, // payload longer than its content
    kCodecNeedsParent = -5,   // a patch below the root decoded without its parent
    kCodecDisabled = -6       // the payload is intact as far as checked, but its decoder is
                              // off in this process (HTJ2K without RIDGE_ALLOW_HTJ2K=1)
};

const char* codecStatusMessage(int status);

struct PatchContext {
    int patch_size = 0;               // samples per side, 2^n + 1
    int level = 0;                    // quadtree level of the patch
    const uint16_t* parent = nullptr; // parent reconstruction (may be null)
    int child_index = 0;              // quadrant within the parent: 0..3 = (x&1)|(y&1)<<1
    // Samples of the patch that cover the level's valid extent (PyramidGeometry::
    // patchSamplesX/Y); 0 = all. A codec may skip the rest (padding): progressive v2 does.
    int samples_x = 0;
    int samples_y = 0;
};

class HeightCodec;

// Learns a codec's per-archive statistics (entropy tables) from the patches it is about to
// code. observe() may be called from several threads at once, with exactly the codes and
// contexts encode() will see; finish() returns the codec to encode with.
//
// A sharded build (pipeline/shard.h) trains one codec across processes: each observes its
// own patches and saves what it saw; one process merges every part, then finishes. What a
// trainer accumulates must therefore not depend on the order of observations or merges
// (integer sums), so that the codec learned is the same for any split into shards or threads.
class CodecTrainer {
  public:
    virtual ~CodecTrainer() = default;
    virtual void observe(const uint16_t* codes, const PatchContext& ctx) = 0;
    virtual std::unique_ptr<HeightCodec> finish() = 0;
    // What was observed so far, for mergeObservations() of a trainer of the same codec, spec
    // and stage.
    virtual std::vector<uint8_t> saveObservations() const = 0;
    // Adds saveObservations()'s bytes; throws ridge::Error for bytes that are not such.
    virtual void mergeObservations(const uint8_t* data, size_t size) = 0;
};

// What one patch's CPU half of a GPU decode hands the GPU (HeightCodec::decodeForGpu): an
// object of the codec's own type that only the GPU decoder registered for that codec reads
// (ridge_render's GPU decoder registry). The stream carries it without knowing what it is.
struct GpuPayload {
    virtual ~GpuPayload() = default;
    virtual size_t bytes() const = 0;       // RAM held, for the decoded-patch cache's budget
    virtual size_t uploadBytes() const = 0; // what the GPU decoder sends for it
};

// How a codec's patches are decoded on the GPU, declared by the codec so that the streamer,
// the planner and the renderer never find it out by its type.
struct GpuDecoding {
    // The coarsest level whose patches decodeForGpu serves (−1: the codec has no GPU half).
    int first_level = -1;
    // Levels below the root read their parent's resident codes (the progressive codec's
    // residuals, the JPEG 2000 residual add): the planner makes the parent resident first.
    bool parent_resident = false;
    // A resident patch may be drawn from a partial decode and refined in place later (the
    // fractal codec: fewer iterations of T); decodeForGpu's payload then says what each step
    // costs in error (GpuPayload subclasses of such codecs implement RefinablePayload).
    bool refinable = false;
    // The CPU half itself reads the parent's codes below the root (the JPEG 2000 codec
    // resolves its exact edges against the prediction): loaders decode ancestors to codes
    // on the CPU first, and the patch is finished on the GPU.
    bool cpu_half_reads_parent = false;
    // HeightCodec::finishOnCpu turns decodeForGpu's payload into codes: a loader that needs
    // the codes of a patch it delivered to the GPU (the parent of a patch whose CPU half reads
    // it) finishes the payload instead of entropy-decoding the blob a second time.
    bool finishes_on_cpu = false;
    bool decodes(int level) const { return first_level >= 0 && level >= first_level; }
};

// The payload of a refinable codec: its steps (iterations) and the bound each leaves.
struct RefinablePayload {
    virtual ~RefinablePayload() = default;
    // Steps of a full decode (what decode() applies).
    virtual int fullSteps() const = 0;
    // Bound on |decode after `steps` − full decode|, codes, for 0 <= steps <= fullSteps()
    // (0 at fullSteps()): what a partial decode adds to the patch's error bound.
    virtual double stepBound(int steps) const = 0;
};

// What a codec lets the stream and the renderer do with its patches, declared by the codec
// (so that nothing finds it out by its type).
struct CodecCapabilities {
    // Decoding a patch below the root needs its parent's reconstruction (needsParent), so
    // loaders decode ancestors first and keep them.
    bool needs_ancestors = false;
    GpuDecoding gpu;
};

class HeightCodec {
  public:
    virtual ~HeightCodec() = default;
    virtual CodecId id() const = 0;
    virtual const char* name() const = 0;
    // True when decode(encode(x)) == x for every patch.
    virtual bool lossless() const = 0;
    // δ_l in code units: bound on |decoded - input| at `level` (0 for lossless codecs).
    virtual double levelErrorBound(int level) const = 0;
    // Worst-case payload size for one patch.
    virtual size_t encodeBound(const PatchContext& ctx) const = 0;
    // Encodes patch_size^2 codes; returns bytes written, 0 if dst_capacity is too small.
    virtual size_t encode(uint8_t* dst, size_t dst_capacity, const uint16_t* codes,
                          const PatchContext& ctx) const = 0;
    // Decodes into dst[patch_size^2]; returns kCodecOk or a negative CodecStatus.
    virtual int decode(uint16_t* dst, const uint8_t* src, size_t src_size,
                       const PatchContext& ctx) const = 0;

    // True when a patch of `level` decodes only with ctx.parent (progressive coding).
    virtual bool needsParent(int /*level*/) const { return false; }
    virtual CodecCapabilities capabilities() const { return {}; }
    // The CPU half of decoding a patch on the GPU (capabilities().gpu.decodes(ctx.level)):
    // parses and entropy-decodes the payload into what the codec's GPU decoder finishes.
    // Returns kCodecOk or a negative CodecStatus; the default has no GPU half.
    virtual int decodeForGpu(const uint8_t* /*src*/, size_t /*src_size*/,
                             const PatchContext& /*ctx*/,
                             std::shared_ptr<const GpuPayload>* /*out*/) const
    {
        return kCodecBadHeader;
    }
    // The GPU half run on the CPU (capabilities().gpu.finishes_on_cpu): the codes decode()
    // gives for the patch whose decodeForGpu returned `payload`, with the same ctx (ctx.parent
    // as decode() reads it). Returns kCodecOk or a negative CodecStatus (kCodecBadHeader for a
    // payload that is not this codec's for ctx); the default cannot.
    virtual int finishOnCpu(const GpuPayload& /*payload*/, const PatchContext& /*ctx*/,
                            uint16_t* /*dst*/) const
    {
        return kCodecBadHeader;
    }
    // What decode(encode(codes)) returns, without coding: the heights a renderer will draw,
    // on which the build measures block errors and min/max. Identity for lossless codecs.
    virtual void reconstruct(const uint16_t* codes, const PatchContext& ctx, uint16_t* out) const;
    // What the archive's metadata records of the codec's variant (build.codec_variant);
    // empty: nothing beyond its name.
    virtual std::string variantDescription() const { return {}; }
    // Codec settings stored in the archive header (codec_param), read back by makeCodec.
    virtual void storeParameters(double param[2]) const { param[0] = param[1] = 0.0; }
    // A codec with per-archive tables: a trainer to learn them before encoding (null: the
    // codec has nothing to learn), and their stored form (the archive's codec tables region,
    // read back through CodecSettings::tables; empty: none).
    virtual std::unique_ptr<CodecTrainer> trainer() const { return nullptr; }
    virtual std::vector<uint8_t> storeTables() const { return {}; }
    // What trainer()s have taught this codec so far (empty: nothing), as bytes from which
    // restoreTraining() on a codec made from the same spec makes this codec again: how a
    // sharded build hands a partly or fully trained codec to other processes.
    virtual std::vector<uint8_t> trainingState() const { return {}; }
    // Throws ridge::Error for bytes that are not trainingState()'s of this codec's spec.
    virtual void restoreTraining(const uint8_t* data, size_t size);
};

// What a codec needs beyond its id: the pyramid depth and the header's codec parameters.
struct CodecSettings {
    int level_count = 1;          // the finest level is level_count - 1
    double param[2] = {0.0, 0.0}; // codec specific (archive header codec_param)
    std::vector<uint8_t> tables;  // the archive's codec tables region (may be empty)
};

// The codec a build codes with, by spec (ridge/codec/codec_registry.h: "NAME[,KEY=VALUE...]");
// `max_error` is the finest-level bound δ_l0 in codes for lossy codecs (ignored by lossless
// ones). Throws ridge::Error for an unknown name or invalid settings, listing the names.
std::unique_ptr<HeightCodec> makeCodec(const std::string& spec, double max_error = 0,
                                       int level_count = 1);
// The codec an archive stores, by its header's id and settings; returns null for an unknown
// id or invalid settings, and then sets *problem (when given) to what is wrong, naming the
// archive header field:
//   "codec_id is 7: must be 0 (raw), 1 (lossless), 2 (progressive) or 3 (jpeg2000)"
//   "codec_param[1] is 3: the progressive codec's variant must be 0, 2, 4 or 6"
std::unique_ptr<HeightCodec> makeCodec(CodecId id, const CodecSettings& settings = {},
                                       std::string* problem = nullptr);
// The id of the codec a valid spec names ("progressive-paper" is a variant of the progressive
// codec); nullopt for an unknown name or invalid options.
std::optional<CodecId> codecIdOf(const std::string& spec);
// True when `spec` names a codec whose decoded heights differ from its input.
bool isLossyCodec(const std::string& spec);
// True when `spec` names a valid codec that a build may encode finest level first (lossless,
// or CodecInfo::finest_first).
bool codecBuildsFinestFirst(const std::string& spec);

} // namespace ridge
