#pragma once
// The progressive L-inf-bounded codec of the hardware-tessellation paper (§4), as a patch
// codec of the .ridge archive (CodecId::Progressive).
//
// Level l is quantized with bound δ_l (level_quantizer.h); the coarsest patch is coded
// directly (MED prediction), every other patch from its parent's reconstruction: refined
// R samples, then A, B, C samples predicted and their errors coded
// (progressive_reconstruction.h), all symbols with the adaptive range coder
// (progressive_entropy.h). Decoding = entropy decode (CPU) + reconstruct (GPU-able).
//
// Payload: u8 'P', u8 version 1, then the range-coded residual stream to the end.
// Variant (archive header codec_param[1]): bit 1 cubic prediction, bit 2 activity contexts
// (bit 0 reserved, 0). codec_param[0] = δ_l0, the finest-level bound in codes (real).
#include "ridge/codec/height_codec.h"
#include "ridge/codec/level_quantizer.h"
#include "ridge/codec/progressive_reconstruction.h"

namespace ridge {

struct ProgressiveVariant {
    OddPredictor predictor = OddPredictor::Cubic;
    bool contexts = true;

    // The paper as written: bilinear prediction, one adaptive model per symbol kind.
    static ProgressiveVariant paper() { return {OddPredictor::Bilinear, false}; }
    int bits() const;
    static ProgressiveVariant fromBits(int bits);
    std::string describe() const;
};

class ProgressiveCodec final : public HeightCodec {
  public:
    // `max_error`: δ_l0 >= 0, the finest-level bound in codes; `level_count`: pyramid levels.
    ProgressiveCodec(double max_error, int level_count, ProgressiveVariant variant = {});

    CodecId id() const override { return CodecId::Progressive; }
    const char* name() const override { return "progressive"; }
    bool lossless() const override { return false; }
    double levelErrorBound(int level) const override;
    size_t encodeBound(const PatchContext& ctx) const override;
    size_t encode(uint8_t* dst, size_t dst_capacity, const uint16_t* codes,
                  const PatchContext& ctx) const override;
    int decode(uint16_t* dst, const uint8_t* src, size_t src_size,
               const PatchContext& ctx) const override;
    bool needsParent(int level) const override { return level > 0; }
    CodecCapabilities capabilities() const override { return {true, this}; }
    void reconstruct(const uint16_t* codes, const PatchContext& ctx, uint16_t* out) const override;
    void storeParameters(double param[2]) const override;

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
    int entropyDecode(const uint8_t* src, size_t src_size, const PatchContext& ctx,
                      int32_t* residuals) const;

    double max_error_;
    int finest_level_;
    ProgressiveVariant variant_;
};

} // namespace ridge
