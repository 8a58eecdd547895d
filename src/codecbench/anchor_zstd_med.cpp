// Quantize + MED + zstd: the simplest strong near-lossless coder one would write by hand, and
// the same back end as ridge's lossless patch codec, so the row shows what the pyramid and
// the progressive codec add over plain prediction.
//
// This work is based on:
//   M. J. Weinberger, G. Seroussi, G. Sapiro, "The LOCO-I Lossless Image Compression
//   Algorithm: Principles and Standardization into JPEG-LS", IEEE TIP 9(8), 2000.
// The median edge detector (MED) predicts from the left (a), upper (b) and upper-left (c)
// indices; residuals are taken modulo 2^16, zig-zagged and stored as 16-bit little-endian.
#include "ridge/codec/med_predictor.h"
#include "ridge/codecbench/anchor_codec.h"

#include "uniform_quantizer.h"

#include <zstd.h>

#include <fmt/core.h>

#include <algorithm>

namespace ridge::codecbench {

namespace {

constexpr int kZstdLevel = 19;

// Residual modulo 2^16 as a signed 16-bit value, zig-zagged so that small magnitudes of
// either sign become small codes.
uint16_t zigZag(uint16_t residual)
{
    const auto r = static_cast<int16_t>(residual);
    return static_cast<uint16_t>((uint16_t(r) << 1) ^ uint16_t(r >> 15));
}

uint16_t unZigZag(uint16_t z)
{
    return static_cast<uint16_t>((z >> 1) ^ uint16_t(-(z & 1)));
}

class MedZstdAnchor final : public AnchorCodec {
  public:
    std::string name() const override { return "MED+zstd"; }
    std::string description() const override
    {
        return fmt::format("quantize to step 2e+1, LOCO-I MED prediction, zig-zag residuals as "
                           "16-bit little-endian, zstd level {} (one frame per tile)",
                           kZstdLevel);
    }
    std::string libraryVersion() const override
    {
        return std::string("zstd ") + ZSTD_versionString();
    }

    std::vector<uint8_t> encode(const uint16_t* codes, int width, int height,
                                int max_error) const override
    {
        const size_t count = size_t(width) * size_t(height);
        const std::vector<uint16_t> q = quantizeCodes(codes, count, max_error);
        std::vector<uint8_t> residuals(count * 2);
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x) {
                const size_t i = size_t(y) * size_t(width) + size_t(x);
                const uint16_t z = zigZag(uint16_t(q[i] - medPredictAt(q.data(), width, x, y)));
                residuals[2 * i] = uint8_t(z & 0xFF);
                residuals[2 * i + 1] = uint8_t(z >> 8);
            }
        std::vector<uint8_t> stream(ZSTD_compressBound(residuals.size()));
        const size_t size = ZSTD_compress(stream.data(), stream.size(), residuals.data(),
                                          residuals.size(), kZstdLevel);
        if (ZSTD_isError(size))
            anchorFail(name(), std::string("zstd: ") + ZSTD_getErrorName(size));
        stream.resize(size);
        return stream;
    }

    void decode(const uint8_t* bytes, size_t size, int width, int height, int max_error,
                uint16_t* codes) const override
    {
        const size_t count = size_t(width) * size_t(height);
        const unsigned long long content = ZSTD_getFrameContentSize(bytes, size);
        if (content != count * 2)
            anchorFail(name(),
                       content == ZSTD_CONTENTSIZE_ERROR || content == ZSTD_CONTENTSIZE_UNKNOWN
                           ? std::string("not a zstd frame with a content size")
                           : fmt::format("frame holds {} bytes, expected {}", content, count * 2));
        std::vector<uint8_t> residuals(count * 2);
        const size_t got = ZSTD_decompress(residuals.data(), residuals.size(), bytes, size);
        if (ZSTD_isError(got))
            anchorFail(name(), std::string("zstd: ") + ZSTD_getErrorName(got));
        if (got != residuals.size())
            anchorFail(name(), fmt::format("frame decoded to {} bytes, expected {}", got,
                                           residuals.size()));
        // Indices are rebuilt in place in `codes` (the predictor only looks back), then
        // dequantized once every prediction is done.
        const uint32_t max_q = maxQuantizedCode(max_error);
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x) {
                const size_t i = size_t(y) * size_t(width) + size_t(x);
                const uint16_t z = uint16_t(residuals[2 * i] | (residuals[2 * i + 1] << 8));
                codes[i] = uint16_t(medPredictAt(codes, width, x, y) + unZigZag(z));
            }
        for (size_t i = 0; i < count; ++i) {
            if (codes[i] > max_q)
                anchorFail(name(),
                           fmt::format("decoded index {} out of range 0..{}", codes[i], max_q));
            codes[i] = dequantizeCode(codes[i], max_error);
        }
    }
};

} // namespace

std::unique_ptr<AnchorCodec> makeMedZstdAnchor()
{
    return std::make_unique<MedZstdAnchor>();
}

} // namespace ridge::codecbench
