#include "ridge/codec/lossless_codec.h"

#include "ridge/codec/med_predictor.h"

#include "ridge/core/target_clones.h"

#include <algorithm>
#include <cstring>
#include <memory>
#include <vector>
#include <zstd.h>

namespace ridge {

namespace {

// Payload layout (all little-endian):
//   u8  magic 'L', u8 version 1
//   zstd frame whose content is 2 * n^2 bytes: low bytes of every zig-zagged MED residual,
//   row-major, then their high bytes.
constexpr uint8_t kMagic = 'L';
constexpr uint8_t kVersion = 1;
constexpr size_t kHeaderSize = 2;

inline uint16_t zigzag(uint16_t residual)
{
    const int16_t r = static_cast<int16_t>(residual);
    return static_cast<uint16_t>((r << 1) ^ (r >> 15));
}

RIDGE_TARGET_CLONES
void encodeInteriorRow(const uint16_t* row, int size, uint8_t* low, uint8_t* high)
{
    const uint16_t* above = row - size;
    for (int x = 1; x < size; ++x) {
        const int pred = medPredict(row[x - 1], above[x], above[x - 1]);
        const uint16_t z = zigzag(static_cast<uint16_t>(row[x] - pred));
        low[x] = static_cast<uint8_t>(z & 0xff);
        high[x] = static_cast<uint8_t>(z >> 8);
    }
}

inline uint16_t unzigzag(uint16_t z)
{
    return static_cast<uint16_t>((z >> 1) ^ -(z & 1));
}

// Per-thread scratch: encode/decode may run concurrently on many patches.
std::vector<uint8_t>& scratch(size_t bytes)
{
    thread_local std::vector<uint8_t> buffer;
    if (buffer.size() < bytes)
        buffer.resize(bytes);
    return buffer;
}

// zstd contexts are reused per thread (creating one costs more than coding a patch).
ZSTD_CCtx* threadCCtx()
{
    thread_local std::unique_ptr<ZSTD_CCtx, size_t (*)(ZSTD_CCtx*)> ctx(ZSTD_createCCtx(),
                                                                        ZSTD_freeCCtx);
    return ctx.get();
}

ZSTD_DCtx* threadDCtx()
{
    thread_local std::unique_ptr<ZSTD_DCtx, size_t (*)(ZSTD_DCtx*)> ctx(ZSTD_createDCtx(),
                                                                        ZSTD_freeDCtx);
    return ctx.get();
}

size_t sampleCount(const PatchContext& ctx)
{
    return static_cast<size_t>(ctx.patch_size) * ctx.patch_size;
}

} // namespace

size_t LosslessCodec::encodeBound(const PatchContext& ctx) const
{
    return kHeaderSize + ZSTD_compressBound(2 * sampleCount(ctx));
}

size_t LosslessCodec::encode(uint8_t* dst, size_t dst_capacity, const uint16_t* codes,
                             const PatchContext& ctx) const
{
    const size_t n = sampleCount(ctx);
    if (dst_capacity < kHeaderSize)
        return 0;
    std::vector<uint8_t>& planes = scratch(2 * n);
    const int size = ctx.patch_size;
    for (int y = 0; y < size; ++y) {
        const size_t row = static_cast<size_t>(y) * size;
        // Border samples (first row, first column) use the special predictions...
        for (int x = 0; x < size; x += (y == 0 ? 1 : size)) {
            const uint16_t z =
                zigzag(static_cast<uint16_t>(codes[row + x] - medPredictAt(codes, size, x, y)));
            planes[row + x] = static_cast<uint8_t>(z & 0xff);
            planes[n + row + x] = static_cast<uint8_t>(z >> 8);
        }
        // ...the interior is independent per sample given the input, so it vectorises.
        if (y > 0)
            encodeInteriorRow(codes + row, size, planes.data() + row, planes.data() + n + row);
    }
    const size_t written =
        ZSTD_compressCCtx(threadCCtx(), dst + kHeaderSize, dst_capacity - kHeaderSize,
                          planes.data(), 2 * n, zstd_level_);
    if (ZSTD_isError(written))
        return 0;
    dst[0] = kMagic;
    dst[1] = kVersion;
    return kHeaderSize + written;
}

int LosslessCodec::decode(uint16_t* dst, const uint8_t* src, size_t src_size,
                          const PatchContext& ctx) const
{
    const size_t n = sampleCount(ctx);
    if (src_size < kHeaderSize)
        return kCodecTruncated;
    if (src[0] != kMagic || src[1] != kVersion)
        return kCodecBadHeader;
    const uint8_t* frame = src + kHeaderSize;
    const size_t frame_size = src_size - kHeaderSize;
    // The frame must hold exactly 2n bytes of content and end exactly at the payload's end.
    const unsigned long long content = ZSTD_getFrameContentSize(frame, frame_size);
    if (content == ZSTD_CONTENTSIZE_ERROR)
        return frame_size < 18 ? kCodecTruncated : kCodecCorrupt;
    if (content != ZSTD_CONTENTSIZE_UNKNOWN && content != 2 * n)
        return kCodecCorrupt;
    const size_t compressed = ZSTD_findFrameCompressedSize(frame, frame_size);
    if (ZSTD_isError(compressed))
        return kCodecTruncated;
    if (compressed != frame_size)
        return kCodecTrailingBytes;

    std::vector<uint8_t>& planes = scratch(2 * n);
    const size_t got = ZSTD_decompressDCtx(threadDCtx(), planes.data(), 2 * n, frame, frame_size);
    if (ZSTD_isError(got) || got != 2 * n)
        return kCodecCorrupt;

    for (int y = 0; y < ctx.patch_size; ++y) {
        for (int x = 0; x < ctx.patch_size; ++x) {
            const size_t i = static_cast<size_t>(y) * ctx.patch_size + x;
            const uint16_t z = static_cast<uint16_t>(planes[i] | (planes[n + i] << 8));
            dst[i] = static_cast<uint16_t>(medPredictAt(dst, ctx.patch_size, x, y) + unzigzag(z));
        }
    }
    return kCodecOk;
}

size_t Raw16Codec::encodeBound(const PatchContext& ctx) const
{
    return 2 * sampleCount(ctx);
}

size_t Raw16Codec::encode(uint8_t* dst, size_t dst_capacity, const uint16_t* codes,
                          const PatchContext& ctx) const
{
    const size_t n = sampleCount(ctx);
    if (dst_capacity < 2 * n)
        return 0;
    for (size_t i = 0; i < n; ++i) {
        dst[2 * i] = static_cast<uint8_t>(codes[i] & 0xff);
        dst[2 * i + 1] = static_cast<uint8_t>(codes[i] >> 8);
    }
    return 2 * n;
}

int Raw16Codec::decode(uint16_t* dst, const uint8_t* src, size_t src_size,
                       const PatchContext& ctx) const
{
    const size_t n = sampleCount(ctx);
    if (src_size < 2 * n)
        return kCodecTruncated;
    if (src_size > 2 * n)
        return kCodecTrailingBytes;
    for (size_t i = 0; i < n; ++i)
        dst[i] = static_cast<uint16_t>(src[2 * i] | (src[2 * i + 1] << 8));
    return kCodecOk;
}

} // namespace ridge
