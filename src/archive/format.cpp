#include "ridge/archive/format.h"

#include "ridge/core/crc32.h"
#include "ridge/core/error.h"
#include "ridge/core/height_grid.h"
#include "ridge/core/parameter_check.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>

#include <zstd.h>

namespace ridge::archive {

namespace {

// Little-endian field access at fixed offsets (the host may be big-endian).
template <typename T> void put(uint8_t* p, T value)
{
    uint8_t bytes[sizeof(T)];
    std::memcpy(bytes, &value, sizeof(T));
    if constexpr (std::endian::native == std::endian::big)
        std::reverse(bytes, bytes + sizeof(T));
    std::memcpy(p, bytes, sizeof(T));
}

template <typename T> T get(const uint8_t* p)
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
    kOffMagic = 0,
    kOffVersion = 8,
    kOffHeaderSize = 12,
    kOffWidth = 16,
    kOffHeight = 20,
    kOffPatchSize = 24,
    kOffLevelCount = 28,
    kOffBlockCells = 32,
    kOffBlockLevels = 36,
    kOffCodec = 40,
    kOffFilter = 44,
    kOffScale = 48,
    kOffOffset = 56,
    kOffSpacingX = 64,
    kOffSpacingY = 72,
    kOffQuantError = 80,
    kOffReserved0 = 88,
    kOffCodecParam = 96,
    kOffMetaOffset = 112,
    kOffMetaSize = 120,
    kOffMetaCrc = 124,
    kOffIndexOffset = 128,
    kOffIndexCrc = 136,
    kOffReserved = 140,
    kOffTablesOffset = 140,
    kOffTablesSize = 148,
    kOffTablesCrc = 152,
    kOffHeaderCrc = 156,
};

// "" when the reserved bytes [begin, end) are zero, else which byte is not.
std::string checkReserved(const uint8_t* in, size_t begin, size_t end)
{
    for (size_t i = begin; i < end; ++i) {
        if (in[i] != 0) {
            char text[96];
            std::snprintf(text, sizeof text,
                          "header reserved bytes %zu..%zu are not zero (byte %zu is 0x%02x)", begin,
                          end - 1, i, unsigned(in[i]));
            return text;
        }
    }
    return {};
}

// "" when `value` lies in `range`, else "header field NAME is VALUE: must be RANGE".
std::string checkField(const char* name, double value, ValueRange range)
{
    if (range.contains(value))
        return {};
    return std::string("header field ") + name + " is " + formatNumber(value) + ": must be " +
           range.describe();
}

// The semantic checks of the numbers (docs/FORMAT.md, "Header"): every height an archive
// can express, its error bounds and its spacings are finite and within the limits shared
// with ingest, so nothing downstream (boxes, cameras, screen-space errors) sees NaN or
// infinity. The first problem found, or "".
std::string checkHeaderValues(const Header& h)
{
    const ValueRange heights = ValueRange::closed(-kMaxAbsHeightMetres, kMaxAbsHeightMetres);
    const ValueRange spacing = ValueRange::openClosed(0, kMaxSpacingMetres);
    if (std::string p = checkField("height_scale", h.height_scale, ValueRange::positive());
        !p.empty())
        return p;
    if (std::string p = checkField("height_offset", h.height_offset, heights); !p.empty())
        return p;
    // metres = offset + scale·code is monotone in the code: codes 0 and 65535 bound them all.
    const double top = h.height_offset + h.height_scale * kMaxCode;
    if (!heights.contains(top))
        return "header fields height_offset + 65535 * height_scale (the height of code 65535) "
               "are " +
               formatNumber(top) + ": must be " + heights.describe();
    if (std::string p = checkField("spacing_x", h.spacing_x, spacing); !p.empty())
        return p;
    if (std::string p = checkField("spacing_y", h.spacing_y, spacing); !p.empty())
        return p;
    // Ingest rounds to the nearest code (an error of about half a code); an error as large as
    // the whole code range would mean the codes say nothing about the source.
    if (std::string p = checkField("quantization_error", h.quantization_error,
                                   ValueRange::closed(0, kMaxCode * h.height_scale));
        !p.empty())
        return p;
    if (h.metadata_size < 2)
        return "header field metadata_size is " + std::to_string(h.metadata_size) +
               ": must be >= 2 (the metadata is a JSON object)";
    return {};
}

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
    put<uint64_t>(out + kOffTablesOffset, h.codec_tables_offset);
    put<uint32_t>(out + kOffTablesSize, h.codec_tables_size);
    put<uint32_t>(out + kOffTablesCrc, h.codec_tables_crc32);
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
        return "header field header_size is " + std::to_string(get<uint32_t>(in + kOffHeaderSize)) +
               ": must be " + std::to_string(kHeaderSize);
    if (std::string p = checkReserved(in, kOffReserved0, kOffCodecParam); !p.empty())
        return p;
    if (h.version < kFirstVersionWithCodecTables)
        if (std::string p = checkReserved(in, kOffReserved, kOffHeaderCrc); !p.empty())
            return p;
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
    h.codec_tables_offset = get<uint64_t>(in + kOffTablesOffset);
    h.codec_tables_size = get<uint32_t>(in + kOffTablesSize);
    h.codec_tables_crc32 = get<uint32_t>(in + kOffTablesCrc);
    return checkHeaderValues(h);
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

std::vector<uint8_t> packIndex(const std::vector<PatchRecord>& records, uint32_t version)
{
    const size_t count = records.size();
    std::vector<uint8_t> entries(count * kIndexEntrySize);
    for (size_t i = 0; i < count; ++i)
        serializeRecord(records[i], entries.data() + i * kIndexEntrySize);
    if (version < kFirstVersionWithPackedIndex)
        return entries;
    std::vector<uint8_t> transposed(entries.size());
    for (size_t i = 0; i < count; ++i)
        for (size_t k = 0; k < kIndexEntrySize; ++k)
            transposed[k * count + i] = entries[i * kIndexEntrySize + k];
    // Level 9: within 2 % of level 19 on real indexes, and fast enough for a planet's.
    std::vector<uint8_t> out(ZSTD_compressBound(transposed.size()));
    const size_t size =
        ZSTD_compress(out.data(), out.size(), transposed.data(), transposed.size(), 9);
    if (ZSTD_isError(size))
        throw Error(std::string("cannot compress the index: ") + ZSTD_getErrorName(size));
    out.resize(size);
    return out;
}

std::string unpackIndex(const uint8_t* data, size_t size, uint64_t count, uint32_t version,
                        std::vector<uint8_t>& entries)
{
    const uint64_t bytes = count * kIndexEntrySize;
    if (version < kFirstVersionWithPackedIndex) {
        if (size != bytes)
            return "index is " + std::to_string(size) + " bytes: " + std::to_string(count) +
                   " patches need " + std::to_string(bytes);
        entries.assign(data, data + size);
        return {};
    }
    const unsigned long long content = ZSTD_getFrameContentSize(data, size);
    if (content == ZSTD_CONTENTSIZE_UNKNOWN || content == ZSTD_CONTENTSIZE_ERROR)
        return "index is not a zstd frame that states its content size";
    if (content != bytes)
        return "index frame holds " + std::to_string(content) + " bytes: " + std::to_string(count) +
               " patches need " + std::to_string(bytes);
    if (ZSTD_findFrameCompressedSize(data, size) != size)
        return "index is not exactly one zstd frame (" + std::to_string(size) +
               " bytes after index_offset)";
    std::vector<uint8_t> transposed(bytes);
    const size_t got = ZSTD_decompress(transposed.data(), transposed.size(), data, size);
    if (ZSTD_isError(got) || got != bytes)
        return "index frame does not decompress to its " + std::to_string(bytes) + " bytes";
    entries.resize(bytes);
    for (uint64_t i = 0; i < count; ++i)
        for (size_t k = 0; k < kIndexEntrySize; ++k)
            entries[i * kIndexEntrySize + k] = transposed[k * count + i];
    return {};
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
