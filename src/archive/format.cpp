#include "ridge/archive/format.h"

#include "ridge/core/crc32.h"

#include <cmath>
#include <algorithm>
#include <bit>
#include <cstring>

namespace ridge::archive {

namespace {

// Little-endian field access at fixed offsets (the host may be big-endian).
template <typename T>
void put(uint8_t* p, T value)
{
    uint8_t bytes[sizeof(T)];
    std::memcpy(bytes, &value, sizeof(T));
    if constexpr (std::endian::native == std::endian::big)
        std::reverse(bytes, bytes + sizeof(T));
    std::memcpy(p, bytes, sizeof(T));
}

template <typename T>
T get(const uint8_t* p)
{
    uint8_t bytes[sizeof(T)];
    std::memcpy(bytes, p, sizeof(T));
    if constexpr (std::endian::native == std::endian::big)
        std::reverse(bytes, bytes + sizeof(T));
    T value;
    std::memcpy(&value, bytes, sizeof(T));
    return value;
}

// Header field offsets (docs/FORMAT.md, "Header").
enum HeaderOffset : size_t {
    kOffMagic = 0, kOffVersion = 8, kOffHeaderSize = 12, kOffWidth = 16, kOffHeight = 20,
    kOffPatchSize = 24, kOffLevelCount = 28, kOffBlockCells = 32, kOffBlockLevels = 36,
    kOffCodec = 40, kOffFilter = 44, kOffScale = 48, kOffOffset = 56, kOffSpacingX = 64,
    kOffSpacingY = 72, kOffQuantError = 80, kOffReserved0 = 88, kOffCodecParam = 96,
    kOffMetaOffset = 112, kOffMetaSize = 120, kOffMetaCrc = 124, kOffIndexOffset = 128,
    kOffIndexCrc = 136, kOffReserved = 140, kOffHeaderCrc = 156,
};

} // namespace

void serializeHeader(const Header& h, uint8_t out[kHeaderSize])
{
    std::memset(out, 0, kHeaderSize);
    std::memcpy(out + kOffMagic, kMagic, sizeof(kMagic));
    put<uint32_t>(out + kOffVersion, kFormatVersion);
    put<uint32_t>(out + kOffHeaderSize, kHeaderSize);
    put<uint32_t>(out + kOffWidth, h.width);
    put<uint32_t>(out + kOffHeight, h.height);
    put<uint32_t>(out + kOffPatchSize, h.patch_size);
    put<uint32_t>(out + kOffLevelCount, h.level_count);
    put<uint32_t>(out + kOffBlockCells, h.block_cells);
    put<uint32_t>(out + kOffBlockLevels, h.block_levels);
    put<uint32_t>(out + kOffCodec, h.codec_id);
    put<uint32_t>(out + kOffFilter, h.filter_id);
    put<double>(out + kOffScale, h.height_scale);
    put<double>(out + kOffOffset, h.height_offset);
    put<double>(out + kOffSpacingX, h.spacing_x);
    put<double>(out + kOffSpacingY, h.spacing_y);
    put<double>(out + kOffQuantError, h.quantization_error);
    put<double>(out + kOffCodecParam, h.codec_param[0]);
    put<double>(out + kOffCodecParam + 8, h.codec_param[1]);
    put<uint64_t>(out + kOffMetaOffset, h.metadata_offset);
    put<uint32_t>(out + kOffMetaSize, h.metadata_size);
    put<uint32_t>(out + kOffMetaCrc, h.metadata_crc32);
    put<uint64_t>(out + kOffIndexOffset, h.index_offset);
    put<uint32_t>(out + kOffIndexCrc, h.index_crc32);
    put<uint32_t>(out + kOffHeaderCrc, crc32(out, kOffHeaderCrc));
}

std::string parseHeader(const uint8_t in[kHeaderSize], Header& h)
{
    if (std::memcmp(in + kOffMagic, kMagic, sizeof(kMagic)) != 0)
        return "not a ridge archive (bad magic)";
    h.version = get<uint32_t>(in + kOffVersion);
    if (h.version == 0 || h.version > kFormatVersion)
        return "format version " + std::to_string(h.version) +
               " is not supported (this reader supports 1.." + std::to_string(kFormatVersion) + ")";
    if (get<uint32_t>(in + kOffHeaderCrc) != crc32(in, kOffHeaderCrc))
        return "header checksum mismatch (corrupt header)";
    if (get<uint32_t>(in + kOffHeaderSize) != kHeaderSize)
        return "unexpected header size";
    h.width = get<uint32_t>(in + kOffWidth);
    h.height = get<uint32_t>(in + kOffHeight);
    h.patch_size = get<uint32_t>(in + kOffPatchSize);
    h.level_count = get<uint32_t>(in + kOffLevelCount);
    h.block_cells = get<uint32_t>(in + kOffBlockCells);
    h.block_levels = get<uint32_t>(in + kOffBlockLevels);
    h.codec_id = get<uint32_t>(in + kOffCodec);
    h.filter_id = get<uint32_t>(in + kOffFilter);
    h.height_scale = get<double>(in + kOffScale);
    h.height_offset = get<double>(in + kOffOffset);
    h.spacing_x = get<double>(in + kOffSpacingX);
    h.spacing_y = get<double>(in + kOffSpacingY);
    h.quantization_error = get<double>(in + kOffQuantError);
    h.codec_param[0] = get<double>(in + kOffCodecParam);
    h.codec_param[1] = get<double>(in + kOffCodecParam + 8);
    h.metadata_offset = get<uint64_t>(in + kOffMetaOffset);
    h.metadata_size = get<uint32_t>(in + kOffMetaSize);
    h.metadata_crc32 = get<uint32_t>(in + kOffMetaCrc);
    h.index_offset = get<uint64_t>(in + kOffIndexOffset);
    h.index_crc32 = get<uint32_t>(in + kOffIndexCrc);
    if (!(h.height_scale > 0) || !std::isfinite(h.height_offset) || !(h.spacing_x > 0) ||
        !(h.spacing_y > 0) || !(h.quantization_error >= 0))
        return "invalid header values";
    return {};
}

void serializeRecord(const PatchRecord& r, uint8_t out[kIndexEntrySize])
{
    put<uint32_t>(out + 0, r.level);
    put<uint32_t>(out + 4, r.x);
    put<uint32_t>(out + 8, r.y);
    put<uint32_t>(out + 12, r.block_errors_size);
    put<uint64_t>(out + 16, r.offset);
    put<uint32_t>(out + 24, r.size);
    put<uint32_t>(out + 28, r.crc32);
    put<float>(out + 32, r.min_height);
    put<float>(out + 36, r.max_height);
    put<float>(out + 40, r.err_appr);
    put<float>(out + 44, r.err);
}

PatchRecord parseRecord(const uint8_t in[kIndexEntrySize])
{
    PatchRecord r;
    r.level = get<uint32_t>(in + 0);
    r.x = get<uint32_t>(in + 4);
    r.y = get<uint32_t>(in + 8);
    r.block_errors_size = get<uint32_t>(in + 12);
    r.offset = get<uint64_t>(in + 16);
    r.size = get<uint32_t>(in + 24);
    r.crc32 = get<uint32_t>(in + 28);
    r.min_height = get<float>(in + 32);
    r.max_height = get<float>(in + 36);
    r.err_appr = get<float>(in + 40);
    r.err = get<float>(in + 44);
    return r;
}

float floatDown(double value)
{
    float f = static_cast<float>(value);
    return static_cast<double>(f) > value ? std::nextafter(f, -INFINITY) : f;
}

float floatUp(double value)
{
    float f = static_cast<float>(value);
    return static_cast<double>(f) < value ? std::nextafter(f, INFINITY) : f;
}

} // namespace ridge::archive
