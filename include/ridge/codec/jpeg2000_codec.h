#pragma once
// The compressed multiresolution model of Yusov & Turlapov (the JPEG2000 paper, §3.4) as a
// patch codec of the .ridge archive (codec id 3).
//
// Progressive encoding (the paper's): the four children of a patch together cover its
// H^Coarse at twice the resolution (H^Fine). Each child predicts its part of H^Fine by
// bilinear interpolation of the parent's *reconstruction* (H̃^Fine), so errors never
// accumulate; the difference layer D = H^Fine − H̃^Fine is quantized to n bits (8 unless the
// criterion needs more) between the patch's d^min and d^max and coded with JPEG 2000. Direct
// encoding (the paper's comparison, and ridge's root patch): H^Fine itself quantized to n
// bits (12 by default) and coded alone.
//
// Rate control (the paper's Figure 7): each patch searches the JPEG 2000 rate until its
// compression criterion holds on every sample — max-abs error ≤ E, or RMS error ≤ E — and
// keeps the smallest codestream that does; the reversible (lossless) wavelet always does, so
// the search always ends. "lossless" codes the n-bit D with the reversible wavelet only (the
// paper's Table 4).
//
// Beyond the paper, for terrain that never cracks: samples on the patch's four edges, which
// neighbours share, do not take JPEG 2000's values but a deterministic one, P + q·(2e+1)
// with q = ⌊(h − P + e)/(2e+1)⌋ from the prediction P (a function of the shared parent edge
// only); q is sent as its difference from what JPEG 2000's value rounds to. Two neighbours
// therefore reconstruct identical edges, and every edge sample is within e of the exact one.
//
// Payload (docs/FORMAT.md "jpeg2000"): u8 'J', u8 1, u8 kind (0 difference layer, 1 direct),
// u8 bits n (1..16), u8 flags (bit 0 reversible wavelet), i32 d_min, u32 step, u32
// border_bytes, the border stream (zstd), then the JPEG 2000 codestream to the end.
// The coded image covers the patch's samples over the valid extent (PatchContext::
// samples_x/y); the rest of the patch repeats its last coded column and row.
#include "ridge/codec/height_codec.h"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace ridge {

inline constexpr CodecId kJpeg2000CodecId{3};

enum class Jpeg2000Encoding : uint8_t { Progressive = 0, Direct = 1 };
// The compression criterion of §3.4.1 (Lossless: the residuals' reversible path, Table 4).
enum class CompressionCriterion : uint8_t { MaxAbs = 0, Rms = 1, Lossless = 2 };
enum class Jpeg2000Library : uint8_t { OpenJpeg = 0, Htj2k = 1 };

struct Jpeg2000Variant {
    // Quantization depth of the paper's tables: 8 bits for D, 12 for direct heights.
    static constexpr int kDifferenceBits = 8;
    static constexpr int kDirectBits = 12;
    // The RMS criterion bounds no sample, yet ridge's error bounds (Err = Err_Appr + δ_l) and
    // `verify --source` need one: under it every sample is also kept within this many times
    // E (the paper's Table 5 measured 19×), and δ_l is that guard.
    static constexpr int kRmsGuardFactor = 32;

    Jpeg2000Encoding encoding = Jpeg2000Encoding::Progressive;
    CompressionCriterion criterion = CompressionCriterion::MaxAbs;
    Jpeg2000Library library = Jpeg2000Library::OpenJpeg;

    // Archive header codec_param[1]: bit 0 direct, bits 1..2 criterion, bit 3 HTJ2K.
    int bits() const;
    static std::optional<Jpeg2000Variant> fromBits(int bits);
    // Parses "jpeg2000[,encoding=progressive|direct][,criterion=max|rms|lossless]
    // [,library=openjpeg|htj2k]"; nullopt for anything else.
    static std::optional<Jpeg2000Variant> fromName(const std::string& name);
    std::string describe() const;
};

// What one patch decodes to before the prediction is added: the n-bit image as coded, its
// dequantization, and the edge samples' values: the CPU half of the GPU residual add (§4),
// what decodeForGpu hands ridge_render's GPU decoder.
struct Jpeg2000Difference final : GpuPayload {
    Jpeg2000Encoding kind = Jpeg2000Encoding::Progressive; // Direct: no parent (P = 0)
    int bits = 8;
    int width = 0, height = 0; // the coded region; the patch repeats beyond it
    int32_t d_min = 0;         // value = d_min + d̂ · step (codes, added to P)
    uint32_t step = 1;
    std::vector<uint16_t> image; // d̂, width x height
    // Final values minus the prediction on the patch's four edges (patch_size each; only
    // the region's part is meaningful): top y = 0, bottom y = C-1, left x = 0, right x = C-1.
    std::vector<int32_t> top, bottom, left, right;

    size_t bytes() const override
    {
        return sizeof(*this) + image.size() * sizeof(uint16_t) +
               (top.size() + bottom.size() + left.size() + right.size()) * sizeof(int32_t);
    }
    // D̂ in 8 bits a sample (16 beyond 8 bits) and the edges.
    size_t uploadBytes() const override
    {
        return image.size() * (bits <= 8 ? 1 : 2) +
               (top.size() + bottom.size() + left.size() + right.size()) * sizeof(int32_t);
    }
};

class Jpeg2000Codec final : public HeightCodec {
  public:
    // `criterion_value`: E in codes (> 0 for max-abs and RMS, >= 0 for lossless).
    Jpeg2000Codec(double criterion_value, int level_count, Jpeg2000Variant variant = {});

    CodecId id() const override { return kJpeg2000CodecId; }
    const char* name() const override { return "jpeg2000"; }
    bool lossless() const override { return false; }
    double levelErrorBound(int level) const override;
    size_t encodeBound(const PatchContext& ctx) const override;
    size_t encode(uint8_t* dst, size_t dst_capacity, const uint16_t* codes,
                  const PatchContext& ctx) const override;
    int decode(uint16_t* dst, const uint8_t* src, size_t src_size,
               const PatchContext& ctx) const override;
    bool needsParent(int level) const override;
    CodecCapabilities capabilities() const override;
    int decodeForGpu(const uint8_t* src, size_t src_size, const PatchContext& ctx,
                     std::shared_ptr<const GpuPayload>* out) const override;
    // addPrediction() after checking that `payload` is decodeForGpu's for a patch of ctx.
    int finishOnCpu(const GpuPayload& payload, const PatchContext& ctx,
                    uint16_t* dst) const override;
    void reconstruct(const uint16_t* codes, const PatchContext& ctx, uint16_t* out) const override;
    void storeParameters(double param[2]) const override;

    // The payload up to the prediction: for a GPU pass that samples the parent itself.
    int decodeDifference(const uint8_t* src, size_t src_size, const PatchContext& ctx,
                         Jpeg2000Difference* out) const;
    // Adds `d` to the bilinear prediction from ctx.parent (or to 0 for a direct patch):
    // exactly what decode() returns.
    static void addPrediction(const Jpeg2000Difference& d, const PatchContext& ctx, uint16_t* dst);

    const Jpeg2000Variant& variant() const { return variant_; }
    double criterionValue() const { return criterion_; }
    // e: the max-abs bound every sample holds, in whole codes (edges use it always).
    int sampleBound() const { return sample_bound_; }
    // The edges' bound, ⌊E⌋ whatever the criterion (shared samples must agree).
    int edgeBound() const { return edge_bound_; }

  private:
    double criterion_;
    Jpeg2000Variant variant_;
    int sample_bound_;
    int edge_bound_;
};

} // namespace ridge
