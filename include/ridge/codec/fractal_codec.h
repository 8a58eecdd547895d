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
// Payload (docs/FORMAT.md, "fractal"): u8 'F', u8 2, u8 iterations N (1..32), u8 flags (0, or
// 1 for the paper's mode: E = 0, no edges, no corrections),
// u16 E, u32 transforms_size, u32 edges_size, u16 × N the bound of each partial decode (k = 0..
// N−1 iterations: max |partial_k − full| in codes; version 1 has none), then three zstd frames: the
// transforms (per range block, raster order: zigzag varints of the domain position less the
// range's, then every s_q as a byte, then zigzag varint differences of o), the edges (zigzag varint
// differences of q_e: top row, bottom row, left then right column without corners) and, to
// the end, the corrections (zigzag varints, interior samples in raster order).
#include "ridge/codec/height_codec.h"

namespace ridge {

inline constexpr CodecId kFractalCodecId{4};

// The CPU half for the GPU decoder (decodeForGpu): what the paper keeps in a texture, per range
// block, and what ridge adds for its bound. Refinable: the GPU may apply k < N iterations and
// more later (Base incremental); stepBound(k) is what that adds to the patch's error.
struct FractalPayload final : GpuPayload, RefinablePayload {
    int iterations = 0; // N: what decode() applies
    int32_t step = 1;   // 2E + 1: a correction's unit
    bool pinned = true; // bounded mode: edges pinned, corrections added (paper mode: neither)
    // 4 per range block, raster order: domain x, domain y (domain grid), s_q, o (codes).
    std::vector<int32_t> transforms;
    // n × n: the pinned value (codes) of each edge sample, the correction q of every other.
    std::vector<int32_t> samples;
    std::vector<uint16_t> step_bounds; // codes, k = 0..N−1; empty for a version 1 payload

    int fullSteps() const override { return iterations; }
    // Infinite for k < N of a version 1 payload (no bound stored: decode fully).
    double stepBound(int steps) const override;
    size_t uploadBytes() const override
    {
        return (transforms.size() + samples.size()) * sizeof(int32_t);
    }
    size_t bytes() const override
    {
        return sizeof(*this) + uploadBytes() + step_bounds.size() * sizeof(uint16_t);
    }
};

struct FractalVariant {
    static constexpr int kDefaultIterations = 8; // the paper's: converged after 8
    static constexpr int kMaxIterations = 32;
    static constexpr int kDefaultSearch = 8;
    static constexpr int kMaxSearch = 1024;
    int iterations = kDefaultIterations; // applications of T when decoding
    // Encoder only: domain blocks searched within this many domain positions of the range
    // block's own (0: all of the patch, the paper's full codebook search).
    int search = kDefaultSearch;
    // The paper's codec as published: transforms only — no pinned edges, no corrections, no
    // bound (levelErrorBound is infinite; codec-bench measures it, archives refuse it).
    bool paper = false;
};

class FractalCodec final : public HeightCodec {
  public:
    // `max_error`: the bound in codes, ⌊max_error⌋ is used (≥ 0; 0 is exact).
    FractalCodec(double max_error, int level_count, FractalVariant variant = {});

    CodecId id() const override { return kFractalCodecId; }
    const char* name() const override { return "fractal"; }
    bool lossless() const override { return false; }
    double levelErrorBound(int) const override;
    size_t encodeBound(const PatchContext& ctx) const override;
    size_t encode(uint8_t* dst, size_t dst_capacity, const uint16_t* codes,
                  const PatchContext& ctx) const override;
    int decode(uint16_t* dst, const uint8_t* src, size_t src_size,
               const PatchContext& ctx) const override;
    void reconstruct(const uint16_t* codes, const PatchContext& ctx, uint16_t* out) const override;
    // Every level decodes on the GPU, by itself (no parent), and may be refined in place.
    CodecCapabilities capabilities() const override { return {false, {0, false, true}}; }
    int decodeForGpu(const uint8_t* src, size_t src_size, const PatchContext& ctx,
                     std::shared_ptr<const GpuPayload>* out) const override;
    std::string variantDescription() const override;
    void storeParameters(double param[2]) const override;

    // The attractor alone after `iterations` (no corrections; edges pinned): what a decoder
    // that stops early draws, for the iterations-against-error curve.
    int decodeAttractor(uint16_t* dst, const uint8_t* src, size_t src_size, const PatchContext& ctx,
                        int iterations) const;
    // What a decoder that stops after `iterations` (clamped to 0..N) draws: that iterate plus
    // the corrections, clamped to codes; decode() at N. Within E + stepBound(iterations) of the
    // patch (FractalPayload).
    int decodePartial(uint16_t* dst, const uint8_t* src, size_t src_size, const PatchContext& ctx,
                      int iterations) const;

    const FractalVariant& variant() const { return variant_; }
    int bound() const { return bound_; }

  private:
    int bound_;
    FractalVariant variant_;
};

} // namespace ridge
