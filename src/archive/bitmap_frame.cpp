#include "bitmap_frame.h"

#include <zstd.h>

namespace ridge::archive::detail {

namespace {

constexpr size_t kPrefix = 1 + 4; // kind, frame_size

} // namespace

std::vector<uint8_t> packBitmapFrame(uint8_t kind,
                                     const std::vector<const std::vector<uint8_t>*>& planes)
{
    size_t bits = 0;
    for (const std::vector<uint8_t>* plane : planes)
        bits += plane->size();
    std::vector<uint8_t> raw((bits + 7) / 8, 0);
    size_t bit = 0;
    for (const std::vector<uint8_t>* plane : planes)
        for (uint8_t b : *plane) {
            if (b)
                raw[bit / 8] |= static_cast<uint8_t>(1u << (bit % 8));
            ++bit;
        }
    std::vector<uint8_t> out(kPrefix + ZSTD_compressBound(raw.size()));
    const size_t frame =
        ZSTD_compress(out.data() + kPrefix, out.size() - kPrefix, raw.data(), raw.size(), 3);
    if (ZSTD_isError(frame))
        return {};
    out[0] = kind;
    const auto size = static_cast<uint32_t>(frame);
    for (int k = 0; k < 4; ++k)
        out[1 + k] = static_cast<uint8_t>(size >> (8 * k));
    out.resize(kPrefix + frame);
    return out;
}

std::string unpackBitmapFrame(const uint8_t* data, size_t size, const char* what,
                              const char* bits_formula,
                              const std::vector<std::vector<uint8_t>*>& planes, size_t& consumed)
{
    const std::string name = what;
    consumed = 0;
    if (size < kPrefix)
        return name + " frame_size missing (blob too short)";
    uint32_t frame = 0;
    for (int k = 0; k < 4; ++k)
        frame |= uint32_t{data[1 + k]} << (8 * k);
    if (frame > size - kPrefix)
        return name + " frame_size is " + std::to_string(frame) + ": must be at most the " +
               std::to_string(size - kPrefix) + " bytes before the payload ends";
    size_t bits = 0;
    for (const std::vector<uint8_t>* plane : planes)
        bits += plane->size();
    const size_t expected = (bits + 7) / 8;
    const uint8_t* z = data + kPrefix;
    const unsigned long long content = ZSTD_getFrameContentSize(z, frame);
    if (content != expected)
        return name + " frame content size is " +
               (content == ZSTD_CONTENTSIZE_UNKNOWN || content == ZSTD_CONTENTSIZE_ERROR
                    ? std::string("not stated")
                    : std::to_string(content)) +
               ": must be " + std::to_string(expected) + " bytes (" + bits_formula + ")";
    if (ZSTD_findFrameCompressedSize(z, frame) != frame)
        return name + " frame is not exactly one zstd frame of frame_size " +
               std::to_string(frame) + " bytes";
    std::vector<uint8_t> raw(expected);
    const size_t got = ZSTD_decompress(raw.data(), raw.size(), z, frame);
    if (ZSTD_isError(got) || got != expected)
        return name + " frame does not decompress to " + std::to_string(expected) + " bytes";
    for (size_t b = bits; b < 8 * expected; ++b)
        if (raw[b / 8] & (1u << (b % 8)))
            return name + " bitmap has a non-zero bit past its last (bit " + std::to_string(b) +
                   ")";
    size_t bit = 0;
    for (std::vector<uint8_t>* plane : planes)
        for (uint8_t& b : *plane) {
            b = (raw[bit / 8] >> (bit % 8)) & 1u;
            ++bit;
        }
    consumed = kPrefix + frame;
    return {};
}

} // namespace ridge::archive::detail
