#pragma once
// The progressive L-inf-bounded codec of the hardware-tessellation paper (§4), as a patch
// codec of the .ridge archive (codec id 2).
//
// Level l is quantized with bound δ_l (level_quantizer.h); the coarsest patch is coded
// directly (MED prediction), every other patch from its parent's reconstruction: refined
// R samples, then A, B, C samples predicted and their errors coded
// (progressive_reconstruction.h), all symbols with the adaptive range coder
// (progressive_entropy.h). Decoding = entropy decode (CPU) + reconstruct (GPU-able).
//
// Three payload formats, chosen by the variant stored in the archive header:
//
// v1 (the paper's codec as ridge first built it): level k levels above the finest has bound
//   e_k = floor(δ_l0 · 2^k); every sample of every patch is coded, R samples as refinements
//   {−1, 0, +1}; adaptive range coding (progressive_entropy.h). Payload: u8 'P', u8 1, then
//   the range-coded residual stream to the end.
// v2: the `nested_levels` finest levels share the finest bound (e_k = δ_l0), the
//   coarser ones grow from there (e_k = floor(δ_l0 · 2^(k − nested + 1))). With decimation a
//   coarse sample *is* a finest sample, so inside the nested zone an R sample's refinement
//   is 0: each patch codes only the samples its parent lacks. Only the coded region
//   (CodedRegion) is coded; static per-archive tables + interleaved rANS
//   (progressive_entropy_v2.h, progressive_tables.h). Payload: u8 'P', u8 2, u8 flags (bit 0:
//   the refinements are coded; other bits 0), then the v2 residual stream to the end.
// v3: v2 with contexts drawn from earlier rows and passes only, so the decoder decodes the
//   rANS lanes side by side (progressive_entropy_v2.h). Payload: u8 'P', u8 3, then as v2.
// v4 (default): v3 with every A, B, C context split by the parent class, how far apart the
//   parent's bins around the sample are (progressive_entropy_v2.h); 3× the tables (tables
//   version 2). The CPU half reads the parent's reconstruction. Payload: u8 'P', u8 4, then
//   as v2.
//
// Variant (archive header codec_param[1]): bit 1 cubic prediction, bit 2 activity contexts,
// bit 3 payload v2, v3 or v4, bits 4..9 nested_levels (v2..v4: 1..32; v1: 0), bit 10 payload
// v3, bit 11 payload v4 (either with bit 3, not both); bit 0 reserved, 0.
// codec_param[0] = δ_l0, the finest-level bound in codes (real).
#include "ridge/codec/height_codec.h"
#include "ridge/codec/level_quantizer.h"
#include "ridge/codec/progressive_reconstruction.h"
#include "ridge/codec/progressive_tables.h"

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace ridge {

inline constexpr CodecId kProgressiveCodecId{2};

// The CPU half's output for the GPU (decodeForGpu, a patch below the root): the entropy-
// decoded residual grid that the GPU turns into codes from the parent's resident codes, in 16
// bits a sample when every one fits (quantised prediction errors nearly always do: it halves
// what a patch holds in the decoded cache and sends), else in 32.
struct ProgressiveResiduals final : GpuPayload {
    std::vector<int16_t> residuals16;
    std::vector<int32_t> residuals32;
    CodedRegion region; // the samples the residuals cover; the rest repeats them

    // Stores `values` in 16 bits when every one fits, else in 32.
    void assign(std::vector<int32_t> values);
    // The residuals in 32 bits, however they are stored: into out[count()], or as a vector.
    size_t count() const { return residuals16.size() + residuals32.size(); }
    void widen(int32_t* out) const;
    std::vector<int32_t> wide() const;
    size_t uploadBytes() const override
    {
        return residuals16.size() * sizeof(int16_t) + residuals32.size() * sizeof(int32_t);
    }
    size_t bytes() const override { return sizeof(*this) + uploadBytes(); }
};

struct ProgressiveVariant {
    // Variant bit 10: payload v3, bit 11: payload v4 (either with bit 3, payload v2's bit).
    static constexpr int kPayloadV3Bit = 1 << 10;
    static constexpr int kPayloadV4Bit = 1 << 11;
    // v2's default number of levels sharing the finest bound (docs/PERF.md, "nested").
    static constexpr int kDefaultNestedLevels = 32;

    OddPredictor predictor = OddPredictor::Cubic;
    bool contexts = true;
    int format = 4;                           // payload version, 1 to 4
    int nested_levels = kDefaultNestedLevels; // v2: 1..32; v1: 1 (its bounds double per level)
    // v2, at build time only: learn least-squares prediction corrections (stored with the
    // tables; an archive without them predicts with P0 alone). Not a stored bit: readers
    // learn it from the tables.
    bool corrections = true;

    // The paper as written: bilinear prediction, one adaptive model per symbol kind.
    static ProgressiveVariant paper() { return {OddPredictor::Bilinear, false, 1, 1, false}; }
    // ridge's first codec: cubic prediction, adaptive activity contexts, payload v1.
    static ProgressiveVariant v1() { return {OddPredictor::Cubic, true, 1, 1, false}; }
    // The default of issue 25 to 30: payload v2 (contexts wait for the previous symbol).
    static ProgressiveVariant v2() { return {OddPredictor::Cubic, true, 2}; }
    // The default of issue 31's first stop: payload v3 (contexts from residuals alone).
    static ProgressiveVariant v3() { return {OddPredictor::Cubic, true, 3}; }
    // Entropy contexts per class of the payload's tables (progressive_tables.h).
    int tableContexts() const
    {
        return format == 4 ? progressive_tables::kContextsV4 : progressive_tables::kContexts;
    }
    int bits() const;
    // Null for bits that name no variant.
    static std::optional<ProgressiveVariant> fromBits(int bits);
    std::string describe() const;
};

class ProgressiveCodec final : public HeightCodec {
  public:
    // `max_error`: δ_l0 >= 0, the finest-level bound in codes; `level_count`: pyramid levels.
    ProgressiveCodec(double max_error, int level_count, ProgressiveVariant variant = {});

    CodecId id() const override { return kProgressiveCodecId; }
    const char* name() const override { return "progressive"; }
    bool lossless() const override { return false; }
    double levelErrorBound(int level) const override;
    size_t encodeBound(const PatchContext& ctx) const override;
    size_t encode(uint8_t* dst, size_t dst_capacity, const uint16_t* codes,
                  const PatchContext& ctx) const override;
    int decode(uint16_t* dst, const uint8_t* src, size_t src_size,
               const PatchContext& ctx) const override;
    bool needsParent(int level) const override { return level > 0; }
    // The paper's split: patches below the root entropy-decode on the CPU and refine +
    // predict + add on the GPU from the parent's resident codes. v4's contexts read the
    // parent's bins, so its CPU half needs the parent's codes too. The GPU half also runs on
    // the CPU (finishOnCpu): a patch delivered as residuals need not be entropy-decoded again
    // for its children.
    CodecCapabilities capabilities() const override
    {
        return {true, {1, true, false, variant_.format == 4, true}};
    }
    int decodeForGpu(const uint8_t* src, size_t src_size, const PatchContext& ctx,
                     std::shared_ptr<const GpuPayload>* out) const override;
    int finishOnCpu(const GpuPayload& payload, const PatchContext& ctx,
                    uint16_t* dst) const override;
    void reconstruct(const uint16_t* codes, const PatchContext& ctx, uint16_t* out) const override;
    std::string variantDescription() const override { return variant_.describe(); }
    void storeParameters(double param[2]) const override;
    std::unique_ptr<CodecTrainer> trainer() const override;
    std::vector<uint8_t> storeTables() const override;
    std::vector<uint8_t> trainingState() const override;
    void restoreTraining(const uint8_t* data, size_t size) override;

    // v2 with these tables and predictor corrections (from the archive, or fitted by
    // trainer()); v1 ignores them. Defaults when never given. `complete`: nothing is left to
    // train (false after the first training stage, the corrections).
    void setTables(std::shared_ptr<const ProgressiveTables> tables, bool complete = true);
    const ProgressiveTables& tables() const { return *tables_; }
    // The samples a patch codes (v1: all of them).
    CodedRegion codedRegion(const PatchContext& ctx) const;
    // The predictor corrections of `level` (v2), null when it has none.
    const PredictorWeights* weights(int level) const { return tables_->weights(level); }
    // The bins of a patch at its level's quantizer, q[n·n].
    void bins(const uint16_t* codes, const PatchContext& ctx, int32_t* q) const;
    // Training stage (v2): 0 nothing learned, 1 predictor corrections, 2 corrections and
    // tables (what an archive's codec always is).
    int trainingStage() const { return training_stage_; }

    // The CPU half of decode() (the paper's split: entropy decoding on the CPU, refine +
    // predict + add on the GPU): the residual grid of a child patch, residuals[n·n], which
    // reconstructChild turns into bins from the parent requantized at quantizer(ctx.level).
    // Returns kCodecOk or a negative CodecStatus. The root (level 0) is reconstructed in
    // raster order and stays with decode().
    int decodeResiduals(const uint8_t* src, size_t src_size, const PatchContext& ctx,
                        int32_t* residuals) const;

    const ProgressiveVariant& variant() const { return variant_; }
    // The quantizer of `level` (0 = coarsest).
    LevelQuantizer quantizer(int level) const;

  private:
    bool validContext(const PatchContext& ctx) const;
    // Header checks and the entropy decoding shared by decode() and decodeResiduals().
    // `parent_bins`: the parent requantized at ctx.level (requantizeParent) when the caller
    // has it, else null (v4 then computes it).
    int entropyDecode(const uint8_t* src, size_t src_size, const PatchContext& ctx,
                      int32_t* residuals, const int32_t* parent_bins = nullptr) const;
    // Bins and residuals of a patch as encode() computes them (the trainer's input too), and
    // below the root the parent's bins at the patch's step (requantizeParent) in
    // parent_bins[n·n]. Returns false for a context encode() rejects.
    bool residualsOf(const uint16_t* codes, const PatchContext& ctx, int32_t* residuals,
                     int32_t* parent_bins) const;
    // decode()'s second half, shared with finishOnCpu(): the residual grid of a patch to its
    // codes (below the root from parent_bins, the parent requantized at ctx.level).
    void reconstructPatch(const int32_t* residuals, const int32_t* parent_bins,
                          const PatchContext& ctx, uint16_t* dst) const;

    double max_error_;
    int finest_level_;
    ProgressiveVariant variant_;
    std::shared_ptr<const ProgressiveTables> tables_;
    int training_stage_ = 0;
};

} // namespace ridge
