#pragma once
// Lossless patch codecs.
//
// Lossless (id 1): MED prediction (LOCO-I / JPEG-LS median edge detector) of every code from
// its west, north and north-west neighbours, residuals mod 2^16 zig-zag mapped, split into a
// low-byte and a high-byte plane (high bytes are almost all zero on terrain) and compressed
// with zstd. zstd is chosen over a hand-written entropy coder because it is fast (>1 GB/s
// decode), fuzzed and maintained; the progressive codec (issue 3) brings ridge's own
// adaptive arithmetic coder where the paper needs it.
//
// Raw16 (id 0): the codes as little-endian uint16, for debugging and as a speed baseline.
#include "ridge/codec/height_codec.h"

namespace ridge {

inline constexpr CodecId kRaw16CodecId{0};
inline constexpr CodecId kLosslessCodecId{1};

class LosslessCodec final : public HeightCodec {
  public:
    explicit LosslessCodec(int zstd_level = 3) : zstd_level_(zstd_level) {}
    CodecId id() const override { return kLosslessCodecId; }
    const char* name() const override { return "lossless"; }
    bool lossless() const override { return true; }
    double levelErrorBound(int) const override { return 0.0; }
    size_t encodeBound(const PatchContext& ctx) const override;
    size_t encode(uint8_t* dst, size_t dst_capacity, const uint16_t* codes,
                  const PatchContext& ctx) const override;
    int decode(uint16_t* dst, const uint8_t* src, size_t src_size,
               const PatchContext& ctx) const override;

  private:
    int zstd_level_;
};

class Raw16Codec final : public HeightCodec {
  public:
    CodecId id() const override { return kRaw16CodecId; }
    const char* name() const override { return "raw"; }
    bool lossless() const override { return true; }
    double levelErrorBound(int) const override { return 0.0; }
    size_t encodeBound(const PatchContext& ctx) const override;
    size_t encode(uint8_t* dst, size_t dst_capacity, const uint16_t* codes,
                  const PatchContext& ctx) const override;
    int decode(uint16_t* dst, const uint8_t* src, size_t src_size,
               const PatchContext& ctx) const override;
};

} // namespace ridge
