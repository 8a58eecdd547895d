#pragma once
// A .ridge archive as bytes, for tests that craft archives a CRC cannot catch: patch a field,
// reseal() every checksum, and only the reader's semantic checks stand between the bytes and
// the renderer. Field offsets are spelled out from docs/FORMAT.md rather than taken from
// src/archive, so a test does not inherit the reader's idea of the layout. Little-endian
// hosts only (x86-64, arm64), as block_error_storage.cpp.
#include "ridge/core/crc32.h"

#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace ridge::test {

// Header field offsets (docs/FORMAT.md, "Header").
namespace header_offset {
inline constexpr size_t kWidth = 16, kHeight = 20, kPatchSize = 24, kLevelCount = 28,
                        kBlockCells = 32, kBlockLevels = 36, kCodecId = 40, kFilterId = 44,
                        kHeightScale = 48, kHeightOffset = 56, kSpacingX = 64, kSpacingY = 72,
                        kQuantizationError = 80, kReserved0 = 88, kCodecParam0 = 96,
                        kCodecParam1 = 104, kMetadataOffset = 112, kMetadataSize = 120,
                        kMetadataCrc = 124, kIndexOffset = 128, kIndexCrc = 136, kReserved1 = 140,
                        kHeaderCrc = 156, kHeaderSize = 160;
} // namespace header_offset

// Index entry field offsets (docs/FORMAT.md, "Index entry").
namespace entry_offset {
inline constexpr size_t kLevel = 0, kX = 4, kY = 8, kBlockErrorsSize = 12, kOffset = 16, kSize = 24,
                        kCrc = 28, kMinHeight = 32, kMaxHeight = 36, kErrAppr = 40, kErr = 44,
                        kEntrySize = 48;
} // namespace entry_offset

class ArchiveBytes {
  public:
    explicit ArchiveBytes(const std::string& path)
    {
        std::ifstream in(path, std::ios::binary);
        if (!in)
            throw std::runtime_error("cannot read " + path);
        bytes_.assign(std::istreambuf_iterator<char>(in), {});
    }
    // Bytes that may be anything (fuzz inputs); reseal() needs at least the 160 header bytes.
    explicit ArchiveBytes(std::vector<uint8_t> bytes) : bytes_(std::move(bytes)) {}
    void save(const std::string& path) const
    {
        std::ofstream out(path, std::ios::binary | std::ios::trunc);
        out.write(reinterpret_cast<const char*>(bytes_.data()),
                  static_cast<std::streamsize>(bytes_.size()));
        if (!out)
            throw std::runtime_error("cannot write " + path);
    }

    std::vector<uint8_t>& bytes() { return bytes_; }

    template <typename T> T get(size_t offset) const
    {
        T value;
        std::memcpy(&value, at(offset, sizeof(T)), sizeof(T));
        return value;
    }
    template <typename T> void set(size_t offset, T value)
    {
        std::memcpy(at(offset, sizeof(T)), &value, sizeof(T));
    }

    uint64_t metadataOffset() const { return get<uint64_t>(header_offset::kMetadataOffset); }
    uint32_t metadataSize() const { return get<uint32_t>(header_offset::kMetadataSize); }
    uint64_t indexOffset() const { return get<uint64_t>(header_offset::kIndexOffset); }
    // Entries between index_offset and the end of the file.
    size_t entryCount() const
    {
        return (bytes_.size() - static_cast<size_t>(indexOffset())) / entry_offset::kEntrySize;
    }
    // File offset of field `field` (entry_offset::k...) of index entry `i`.
    size_t entryField(size_t i, size_t field) const
    {
        return static_cast<size_t>(indexOffset()) + i * entry_offset::kEntrySize + field;
    }
    template <typename T> T entry(size_t i, size_t field) const
    {
        return get<T>(entryField(i, field));
    }
    template <typename T> void setEntry(size_t i, size_t field, T value)
    {
        set<T>(entryField(i, field), value);
    }

    std::string metadata() const
    {
        const uint8_t* p = at(static_cast<size_t>(metadataOffset()), metadataSize());
        return std::string(reinterpret_cast<const char*>(p), metadataSize());
    }
    // Replaces the metadata document; the index moves to follow it (index_offset updated).
    void setMetadata(const std::string& json)
    {
        const size_t begin = static_cast<size_t>(metadataOffset());
        const size_t end = begin + metadataSize();
        bytes_.erase(bytes_.begin() + static_cast<std::ptrdiff_t>(begin),
                     bytes_.begin() + static_cast<std::ptrdiff_t>(end));
        bytes_.insert(bytes_.begin() + static_cast<std::ptrdiff_t>(begin), json.begin(),
                      json.end());
        set<uint32_t>(header_offset::kMetadataSize, static_cast<uint32_t>(json.size()));
        set<uint64_t>(header_offset::kIndexOffset, begin + json.size());
    }

    // Recomputes every checksum from the bytes as they are now: each blob's (stored in its
    // index entry; blobs that lie outside the file are left alone), the metadata's, the
    // index's, then the header's, in that order because each covers the previous.
    void reseal()
    {
        const size_t index = static_cast<size_t>(indexOffset());
        if (index <= bytes_.size()) {
            for (size_t i = 0; i < entryCount(); ++i) {
                const uint64_t offset = entry<uint64_t>(i, entry_offset::kOffset);
                const uint32_t size = entry<uint32_t>(i, entry_offset::kSize);
                if (offset <= bytes_.size() && size <= bytes_.size() - offset)
                    setEntry<uint32_t>(i, entry_offset::kCrc, crc32(bytes_.data() + offset, size));
            }
            set<uint32_t>(header_offset::kIndexCrc,
                          crc32(bytes_.data() + index, bytes_.size() - index));
        }
        const uint64_t meta = metadataOffset();
        if (meta <= bytes_.size() && metadataSize() <= bytes_.size() - meta)
            set<uint32_t>(header_offset::kMetadataCrc, crc32(bytes_.data() + meta, metadataSize()));
        set<uint32_t>(header_offset::kHeaderCrc, crc32(bytes_.data(), header_offset::kHeaderCrc));
    }

  private:
    uint8_t* at(size_t offset, size_t size)
    {
        if (offset > bytes_.size() || size > bytes_.size() - offset)
            throw std::out_of_range("archive bytes: " + std::to_string(size) + " bytes at " +
                                    std::to_string(offset) + " are outside the file");
        return bytes_.data() + offset;
    }
    const uint8_t* at(size_t offset, size_t size) const
    {
        return const_cast<ArchiveBytes*>(this)->at(offset, size);
    }

    std::vector<uint8_t> bytes_;
};

} // namespace ridge::test
