#pragma once
// The fractal (PIFS) height codec of Erra, Scarano & Guida (the fractal-rings paper, §7) as a
// patch codec of the .ridge archive (codec id 4), with a bound that holds on every sample.
//
// Each patch is coded by itself (no parent): its range blocks' transforms (src/codec/fractal/
// pifs.h: domain block, s, o), decoded by iterating T from a fixed start image. Beyond the
// paper, for a bound E (whole codes) on every sample of every level:
//   * the patch's four edges, which neighbouring patches share, are sent as q_e with
//     value = (2E + 1)·q_e, q_e = ⌊(h + E)/(2E + 1)⌋ — a function of the exact height alone, so
//     neighbours reconstruct identical edges — and are pinned during the iteration;
//   * every other sample gets a correction q = ⌊(h − a + E)/(2E + 1)⌋ from the attractor a,
//     value = a + (2E + 1)·q: within E whatever the attractor. Where the attractor is already
//     within E, q is 0, which costs almost nothing after zstd.
// Decoding is integer arithmetic throughout, so any decoder that follows pifs.h reproduces it
// bit for bit.
//
// Payload (docs/FORMAT.md, "fractal"): u8 'F', u8 1, u8 iterations (1..32), u8 flags (0),
// u16 E, u32 transforms_size, u32 edges_size, then three zstd frames: the transforms (per
// range block, raster order: zigzag varints of the domain position less the range's, then
// every s_q as a byte, then zigzag varint differences of o), the edges (zigzag varint
// differences of q_e: top row, bottom row, left then right column without corners) and, to
// the end, the corrections (zigzag varints, interior samples in raster order).
#include "ridge/codec/height_codec.h"

namespace ridge {

inline constexpr CodecId kFractalCodecId{4};

struct FractalVariant {
    static constexpr int kDefaultIterations = 8; // the paper's: converged after 8
    static constexpr int kMaxIterations = 32;
    static constexpr int kDefaultSearch = 8;
    static constexpr int kMaxSearch = 1024;
    int iterations = kDefaultIterations; // applications of T when decoding
    // Encoder only: domain blocks searched within this many domain positions of the range
    // block's own (0: all of the patch, the paper's full codebook search).
    int search = kDefaultSearch;
};

class FractalCodec final : public HeightCodec {
  public:
    // `max_error`: the bound in codes, ⌊max_error⌋ is used (≥ 0; 0 is exact).
    FractalCodec(double max_error, int level_count, FractalVariant variant = {});

    CodecId id() const override { return kFractalCodecId; }
    const char* name() const override { return "fractal"; }
    bool lossless() const override { return false; }
    double levelErrorBound(int) const override { return bound_; }
    size_t encodeBound(const PatchContext& ctx) const override;
    size_t encode(uint8_t* dst, size_t dst_capacity, const uint16_t* codes,
                  const PatchContext& ctx) const override;
    int decode(uint16_t* dst, const uint8_t* src, size_t src_size,
               const PatchContext& ctx) const override;
    void reconstruct(const uint16_t* codes, const PatchContext& ctx, uint16_t* out) const override;
    std::string variantDescription() const override;
    void storeParameters(double param[2]) const override;

    // The attractor alone after `iterations` (no corrections; edges pinned): what a decoder
    // that stops early draws, for the iterations-against-error curve.
    int decodeAttractor(uint16_t* dst, const uint8_t* src, size_t src_size, const PatchContext& ctx,
                        int iterations) const;

    const FractalVariant& variant() const { return variant_; }
    int bound() const { return bound_; }

  private:
    int bound_;
    FractalVariant variant_;
};

} // namespace ridge
