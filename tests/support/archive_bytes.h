#pragma once
// A .ridge archive as bytes, for tests that craft archives a CRC cannot catch: patch a field,
// reseal() every checksum, and only the reader's semantic checks stand between the bytes and
// the renderer. Field offsets are spelled out from docs/FORMAT.md rather than taken from
// src/archive, so a test does not inherit the reader's idea of the layout. Little-endian
// hosts only (x86-64, arm64), as block_error_storage.cpp.
//
// From format version 5 the index is one zstd frame of byte-transposed entries: the entries
// are then kept unpacked here, entry() and setEntry() edit them, and reseal() and save()
// pack them again (an index that does not unpack stays raw bytes, edited in place).
#include "ridge/archive/format.h"
#include "ridge/core/crc32.h"

#include <zstd.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <string_view>
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
        unpackIndex();
    }
    // Bytes that may be anything (fuzz inputs); reseal() needs at least the 160 header bytes.
    explicit ArchiveBytes(std::vector<uint8_t> bytes) : bytes_(std::move(bytes)) { unpackIndex(); }
    void save(const std::string& path) const
    {
        const std::vector<uint8_t> packed = packedBytes();
        const std::vector<uint8_t>& b = dirty_ ? packed : bytes_;
        std::ofstream out(path, std::ios::binary | std::ios::trunc);
        out.write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
        if (!out)
            throw std::runtime_error("cannot write " + path);
    }

    // The file's bytes. With a packed index (version 5) edited through setEntry(), its region
    // holds the entries as they were until reseal() or pack().
    std::vector<uint8_t>& bytes() { return bytes_; }
    // Writes edited entries of a packed index back into the file's bytes (reseal() does).
    void pack()
    {
        if (dirty_)
            bytes_ = packedBytes();
        dirty_ = false;
    }
    bool packedIndex() const { return packed_; }
    // Format 6 on: the metadata region is a zstd frame (metadata() unpacks it).
    bool packedMetadata() const { return bytes_.size() >= 12 && get<uint32_t>(8) >= 6; }
    // Replaces the index region with `region`, bytes that need not hold entries (a crafted
    // frame): reseal() then only recomputes the index's checksum, not the blobs'.
    void setOpaqueIndex(const std::vector<uint8_t>& region)
    {
        bytes_.resize(std::min(static_cast<size_t>(indexOffset()), bytes_.size()));
        bytes_.insert(bytes_.end(), region.begin(), region.end());
        packed_ = dirty_ = false;
        entries_.clear();
        opaque_ = true;
    }
    // Stores a packed index's entries as they are (the layout of versions 1..4), for an
    // archive rewritten as an older version; set the version before reseal().
    void storeIndexUnpacked()
    {
        if (!packed_)
            return;
        bytes_.resize(std::min(static_cast<size_t>(indexOffset()), bytes_.size()));
        bytes_.insert(bytes_.end(), entries_.begin(), entries_.end());
        packed_ = dirty_ = false;
        entries_.clear();
    }

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
    // Entries of the index: between index_offset and the end of the file, or those the
    // packed index holds.
    size_t entryCount() const
    {
        if (packed_)
            return entries_.size() / entry_offset::kEntrySize;
        return (bytes_.size() - static_cast<size_t>(indexOffset())) / entry_offset::kEntrySize;
    }
    template <typename T> T entry(size_t i, size_t field) const
    {
        if (!packed_)
            return get<T>(entryField(i, field));
        T value;
        std::memcpy(&value, entryAt(i, field, sizeof(T)), sizeof(T));
        return value;
    }
    template <typename T> void setEntry(size_t i, size_t field, T value)
    {
        if (!packed_)
            return set<T>(entryField(i, field), value);
        std::memcpy(const_cast<uint8_t*>(entryAt(i, field, sizeof(T))), &value, sizeof(T));
        dirty_ = true;
    }

    // The metadata document; from version 6 the region is one zstd frame coded against the
    // format's metadata reference, which this unpacks and setMetadata() packs again (the
    // reference is the format's constant, taken from the library; the framing is spelled out
    // here, as the index's is).
    std::string metadata() const
    {
        const std::vector<uint8_t> region = metadataRegion();
        if (!packedMetadata())
            return std::string(region.begin(), region.end());
        const unsigned long long content = ZSTD_getFrameContentSize(region.data(), region.size());
        if (content == ZSTD_CONTENTSIZE_UNKNOWN || content == ZSTD_CONTENTSIZE_ERROR ||
            content > (uint64_t{1} << 28))
            throw std::runtime_error("archive bytes: the metadata is not a frame to unpack");
        const std::string_view reference = archive::metadataReference();
        std::string json(content, '\0');
        ZSTD_DCtx* dctx = ZSTD_createDCtx();
        ZSTD_DCtx_refPrefix(dctx, reference.data(), reference.size());
        const size_t got =
            ZSTD_decompressDCtx(dctx, json.data(), json.size(), region.data(), region.size());
        ZSTD_freeDCtx(dctx);
        if (ZSTD_isError(got) || got != json.size())
            throw std::runtime_error("archive bytes: the metadata frame does not unpack");
        return json;
    }
    // Replaces the metadata document (packed as ridge packs it from version 6: zstd level 19
    // against the reference); the index moves to follow it (index_offset updated).
    void setMetadata(const std::string& json)
    {
        if (!packedMetadata())
            return setMetadataRegion(std::vector<uint8_t>(json.begin(), json.end()));
        const std::string_view reference = archive::metadataReference();
        std::vector<uint8_t> frame(ZSTD_compressBound(json.size()));
        ZSTD_CCtx* cctx = ZSTD_createCCtx();
        ZSTD_CCtx_setParameter(cctx, ZSTD_c_compressionLevel, 19);
        ZSTD_CCtx_refPrefix(cctx, reference.data(), reference.size());
        const size_t size =
            ZSTD_compress2(cctx, frame.data(), frame.size(), json.data(), json.size());
        ZSTD_freeCCtx(cctx);
        if (ZSTD_isError(size))
            throw std::runtime_error("archive bytes: cannot pack the metadata");
        frame.resize(size);
        setMetadataRegion(frame);
    }
    // Stores the metadata document as it is, as versions before 6 do (for a test that rewrites
    // an archive into an older version: set the header's version next).
    void storeMetadataUnpacked()
    {
        if (!packedMetadata())
            return;
        const std::string json = metadata();
        setMetadataRegion(std::vector<uint8_t>(json.begin(), json.end()));
    }
    // The metadata region's bytes as stored, and their replacement (a crafted region); the
    // index moves to follow it.
    std::vector<uint8_t> metadataRegion() const
    {
        const uint8_t* p = at(static_cast<size_t>(metadataOffset()), metadataSize());
        return std::vector<uint8_t>(p, p + metadataSize());
    }
    void setMetadataRegion(const std::vector<uint8_t>& region)
    {
        const size_t begin = static_cast<size_t>(metadataOffset());
        const size_t end = begin + metadataSize();
        bytes_.erase(bytes_.begin() + static_cast<std::ptrdiff_t>(begin),
                     bytes_.begin() + static_cast<std::ptrdiff_t>(end));
        bytes_.insert(bytes_.begin() + static_cast<std::ptrdiff_t>(begin), region.begin(),
                      region.end());
        set<uint32_t>(header_offset::kMetadataSize, static_cast<uint32_t>(region.size()));
        set<uint64_t>(header_offset::kIndexOffset, begin + region.size());
    }

    // Recomputes every checksum from the bytes as they are now: each blob's (stored in its
    // index entry; blobs that lie outside the file are left alone), the metadata's, the
    // index's, then the header's, in that order because each covers the previous.
    void reseal()
    {
        const size_t index = static_cast<size_t>(indexOffset());
        // An index that starts inside the header (a fuzzed index_offset) is not resealed:
        // its entries' checksums would be written over the header's fields, index_offset
        // among them (the reader refuses such a file by its offsets anyway).
        if (index >= header_offset::kHeaderSize && index <= bytes_.size()) {
            for (size_t i = 0; i < (opaque_ ? 0 : entryCount()); ++i) {
                const uint64_t offset = entry<uint64_t>(i, entry_offset::kOffset);
                const uint32_t size = entry<uint32_t>(i, entry_offset::kSize);
                if (offset <= bytes_.size() && size <= bytes_.size() - offset)
                    setEntry<uint32_t>(i, entry_offset::kCrc, crc32(bytes_.data() + offset, size));
            }
            pack();
            set<uint32_t>(header_offset::kIndexCrc,
                          crc32(bytes_.data() + index, bytes_.size() - index));
        }
        const uint64_t meta = metadataOffset();
        if (meta <= bytes_.size() && metadataSize() <= bytes_.size() - meta)
            set<uint32_t>(header_offset::kMetadataCrc, crc32(bytes_.data() + meta, metadataSize()));
        set<uint32_t>(header_offset::kHeaderCrc, crc32(bytes_.data(), header_offset::kHeaderCrc));
    }

  private:
    // File offset of field `field` (entry_offset::k...) of index entry `i` (raw index).
    size_t entryField(size_t i, size_t field) const
    {
        return static_cast<size_t>(indexOffset()) + i * entry_offset::kEntrySize + field;
    }
    const uint8_t* entryAt(size_t i, size_t field, size_t size) const
    {
        const size_t offset = i * entry_offset::kEntrySize + field;
        if (offset > entries_.size() || size > entries_.size() - offset)
            throw std::out_of_range("archive bytes: entry " + std::to_string(i) +
                                    " is outside the index");
        return entries_.data() + offset;
    }

    // Version 5 on: the index region as one zstd frame of byte-transposed entries
    // (docs/FORMAT.md, "Index"). Left raw when the bytes are not that.
    void unpackIndex()
    {
        if (bytes_.size() < header_offset::kHeaderSize || get<uint32_t>(8) < 5)
            return;
        const uint64_t index = indexOffset();
        if (index > bytes_.size())
            return;
        const uint8_t* z = bytes_.data() + index;
        const size_t size = bytes_.size() - size_t(index);
        const unsigned long long content = ZSTD_getFrameContentSize(z, size);
        if (content == ZSTD_CONTENTSIZE_UNKNOWN || content == ZSTD_CONTENTSIZE_ERROR ||
            content % entry_offset::kEntrySize != 0 || content > (uint64_t{1} << 28) ||
            ZSTD_findFrameCompressedSize(z, size) != size)
            return;
        std::vector<uint8_t> transposed(content);
        if (ZSTD_decompress(transposed.data(), transposed.size(), z, size) != content)
            return;
        const size_t count = content / entry_offset::kEntrySize;
        entries_.resize(content);
        for (size_t i = 0; i < count; ++i)
            for (size_t k = 0; k < entry_offset::kEntrySize; ++k)
                entries_[i * entry_offset::kEntrySize + k] = transposed[k * count + i];
        packed_ = true;
    }
    // The file with the entries packed again after index_offset (what ridge writes: zstd
    // level 9).
    std::vector<uint8_t> packedBytes() const
    {
        const size_t count = entries_.size() / entry_offset::kEntrySize;
        std::vector<uint8_t> transposed(entries_.size());
        for (size_t i = 0; i < count; ++i)
            for (size_t k = 0; k < entry_offset::kEntrySize; ++k)
                transposed[k * count + i] = entries_[i * entry_offset::kEntrySize + k];
        std::vector<uint8_t> frame(ZSTD_compressBound(transposed.size()));
        const size_t size =
            ZSTD_compress(frame.data(), frame.size(), transposed.data(), transposed.size(), 9);
        if (ZSTD_isError(size))
            throw std::runtime_error("archive bytes: cannot pack the index");
        const size_t index = std::min(static_cast<size_t>(indexOffset()), bytes_.size());
        std::vector<uint8_t> out(bytes_.begin(), bytes_.begin() + std::ptrdiff_t(index));
        out.insert(out.end(), frame.begin(), frame.begin() + std::ptrdiff_t(size));
        return out;
    }

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
    bool packed_ = false; // version 5: the index is kept unpacked in entries_
    bool dirty_ = false;  // entries_ edited since the index was last packed into bytes_
    bool opaque_ = false; // setOpaqueIndex(): the region holds no entries to reseal
    std::vector<uint8_t> entries_;
};

} // namespace ridge::test
