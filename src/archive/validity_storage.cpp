#include "ridge/archive/validity_storage.h"

#include <zstd.h>

#include <cstring>

namespace ridge::archive {

namespace {

constexpr uint8_t kKindAll = 0, kKindNone = 1, kKindBitmap = 2;
constexpr size_t kBitmapPrefix = 1 + 4; // kind, frame_size

size_t bitmapBytes(int n)
{
    const size_t bits = static_cast<size_t>(n) * n + static_cast<size_t>(n - 1) * (n - 1);
    return (bits + 7) / 8;
}

} // namespace

std::vector<uint8_t> packValidity(const PatchValidity& validity, int patch_size)
{
    PatchValidity v = validity;
    v.canonicalize();
    if (v.kind == PatchValidity::Kind::AllValid)
        return {kKindAll};
    if (v.kind == PatchValidity::Kind::NoneValid)
        return {kKindNone};
    const int n = patch_size;
    std::vector<uint8_t> raw(bitmapBytes(n), 0);
    size_t bit = 0;
    for (const std::vector<uint8_t>* plane : {&v.samples, &v.cells})
        for (uint8_t b : *plane) {
            if (b)
                raw[bit / 8] |= static_cast<uint8_t>(1u << (bit % 8));
            ++bit;
        }
    std::vector<uint8_t> out(kBitmapPrefix + ZSTD_compressBound(raw.size()));
    const size_t frame = ZSTD_compress(out.data() + kBitmapPrefix, out.size() - kBitmapPrefix,
                                       raw.data(), raw.size(), 3);
    if (ZSTD_isError(frame))
        return {};
    out[0] = kKindBitmap;
    const uint32_t size = static_cast<uint32_t>(frame);
    for (int k = 0; k < 4; ++k)
        out[1 + k] = static_cast<uint8_t>(size >> (8 * k));
    out.resize(kBitmapPrefix + frame);
    return out;
}

std::string unpackValidity(const uint8_t* data, size_t size, int patch_size, bool corners_rule,
                           PatchValidity& out, size_t& consumed)
{
    const int n = patch_size, c = n - 1;
    out = PatchValidity{};
    out.patch_size = n;
    consumed = 0;
    if (size < 1)
        return "validity mask missing (blob ends after its block errors)";
    if (data[0] == kKindAll || data[0] == kKindNone) {
        out.kind = data[0] == kKindAll ? PatchValidity::Kind::AllValid : PatchValidity::Kind::NoneValid;
        consumed = 1;
        return {};
    }
    if (data[0] != kKindBitmap)
        return "validity kind is " + std::to_string(data[0]) +
               ": must be 0 (all valid), 1 (none valid) or 2 (bitmap)";
    if (size < kBitmapPrefix)
        return "validity frame_size missing (blob too short)";
    uint32_t frame = 0;
    for (int k = 0; k < 4; ++k)
        frame |= uint32_t{data[1 + k]} << (8 * k);
    if (frame > size - kBitmapPrefix)
        return "validity frame_size is " + std::to_string(frame) + ": must be at most the " +
               std::to_string(size - kBitmapPrefix) + " bytes before the payload ends";
    const uint8_t* z = data + kBitmapPrefix;
    const size_t expected = bitmapBytes(n);
    const unsigned long long content = ZSTD_getFrameContentSize(z, frame);
    if (content != expected)
        return "validity frame content size is " +
               (content == ZSTD_CONTENTSIZE_UNKNOWN || content == ZSTD_CONTENTSIZE_ERROR
                    ? std::string("not stated")
                    : std::to_string(content)) +
               ": must be " + std::to_string(expected) + " bytes (ceil((n² + (n−1)²) / 8))";
    if (ZSTD_findFrameCompressedSize(z, frame) != frame)
        return "validity frame is not exactly one zstd frame of frame_size " +
               std::to_string(frame) + " bytes";
    std::vector<uint8_t> raw(expected);
    const size_t got = ZSTD_decompress(raw.data(), raw.size(), z, frame);
    if (ZSTD_isError(got) || got != expected)
        return "validity frame does not decompress to " + std::to_string(expected) + " bytes";
    const size_t bits = static_cast<size_t>(n) * n + static_cast<size_t>(c) * c;
    for (size_t b = bits; b < 8 * expected; ++b)
        if (raw[b / 8] & (1u << (b % 8)))
            return "validity bitmap has a non-zero bit past its last (bit " + std::to_string(b) + ")";
    out.kind = PatchValidity::Kind::Mixed;
    out.samples.resize(static_cast<size_t>(n) * n);
    out.cells.resize(static_cast<size_t>(c) * c);
    size_t bit = 0;
    for (std::vector<uint8_t>* plane : {&out.samples, &out.cells})
        for (uint8_t& b : *plane) {
            b = (raw[bit / 8] >> (bit % 8)) & 1u;
            ++bit;
        }
    PatchValidity canonical = out;
    canonical.canonicalize();
    if (canonical.kind != PatchValidity::Kind::Mixed)
        return std::string("validity bitmap is uniform (") +
               (canonical.kind == PatchValidity::Kind::AllValid ? "all valid" : "none valid") +
               "): must be stored as kind " +
               (canonical.kind == PatchValidity::Kind::AllValid ? "0" : "1");
    if (corners_rule)
        for (int j = 0; j < c; ++j)
            for (int i = 0; i < c; ++i)
                if (out.cellDrawable(i, j) &&
                    !(out.sampleValid(i, j) && out.sampleValid(i + 1, j) &&
                      out.sampleValid(i, j + 1) && out.sampleValid(i + 1, j + 1)))
                    return "validity cell (" + std::to_string(i) + ", " + std::to_string(j) +
                           ") is drawable but a corner sample is not valid";
    consumed = kBitmapPrefix + frame;
    return {};
}

} // namespace ridge::archive
