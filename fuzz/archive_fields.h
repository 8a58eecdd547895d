#pragma once
// Where the fields of a (possibly damaged) .ridge archive lie, for the structure-aware fuzz
// target's mutator: header fields and index entry fields at their docs/FORMAT.md offsets
// (tests/support/archive_bytes.h spells them out), checksums excluded since every input is
// resealed before it is opened; regions that change size go through archive_craft.h.
#include "archive_bytes.h"
#include "archive_craft.h"

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <iterator>

namespace ridge::fuzz {

enum class FieldType { U32, U64, F32, F64 };
inline size_t fieldBytes(FieldType t)
{
    return t == FieldType::U64 || t == FieldType::F64 ? 8 : 4;
}

struct Field {
    size_t offset = 0;
    FieldType type = FieldType::U32;
};

struct Region {
    size_t offset = 0, size = 0;
};

namespace h = test::header_offset;
namespace e = test::entry_offset;

// Every header field but the magic and the checksums; reserved words included.
inline constexpr Field kHeaderFields[] = {
    {8, FieldType::U32},  // version
    {12, FieldType::U32}, // header_size
    {h::kWidth, FieldType::U32},
    {h::kHeight, FieldType::U32},
    {h::kPatchSize, FieldType::U32},
    {h::kLevelCount, FieldType::U32},
    {h::kBlockCells, FieldType::U32},
    {h::kBlockLevels, FieldType::U32},
    {h::kCodecId, FieldType::U32},
    {h::kFilterId, FieldType::U32},
    {h::kHeightScale, FieldType::F64},
    {h::kHeightOffset, FieldType::F64},
    {h::kSpacingX, FieldType::F64},
    {h::kSpacingY, FieldType::F64},
    {h::kQuantizationError, FieldType::F64},
    {h::kReserved0, FieldType::U64},
    {h::kCodecParam0, FieldType::F64},
    {h::kCodecParam1, FieldType::F64},
    {h::kMetadataOffset, FieldType::U64},
    {h::kMetadataSize, FieldType::U32},
    {h::kIndexOffset, FieldType::U64},
    {h::kReserved1, FieldType::U32},
    {h::kReserved1 + 4, FieldType::U64},
    {h::kReserved1 + 12, FieldType::U32},
};
// Index entry fields relative to the entry (its crc32 excluded).
inline constexpr Field kEntryFields[] = {
    {e::kLevel, FieldType::U32},     {e::kX, FieldType::U32},
    {e::kY, FieldType::U32},         {e::kBlockErrorsSize, FieldType::U32},
    {e::kOffset, FieldType::U64},    {e::kSize, FieldType::U32},
    {e::kMinHeight, FieldType::F32}, {e::kMaxHeight, FieldType::F32},
    {e::kErrAppr, FieldType::F32},   {e::kErr, FieldType::F32},
};

// The regions of `data` as far as its header says, clamped to the file.
struct ArchiveLayout {
    bool valid = false;
    Region metadata;
    bool packed_metadata = false; // format 6: the region is a zstd frame, not the JSON
    size_t index_offset = 0;
    size_t entries = 0;

    static ArchiveLayout of(const uint8_t* data, size_t size)
    {
        ArchiveLayout l;
        if (size < h::kHeaderSize)
            return l;
        uint64_t meta_offset, index;
        uint32_t meta_size;
        std::memcpy(&meta_offset, data + h::kMetadataOffset, 8);
        std::memcpy(&meta_size, data + h::kMetadataSize, 4);
        std::memcpy(&index, data + h::kIndexOffset, 8);
        if (meta_offset <= size && meta_size <= size - meta_offset)
            l.metadata = {size_t(meta_offset), size_t(meta_size)};
        uint32_t version;
        std::memcpy(&version, data + 8, 4);
        // Version 5's index is packed (zstd): its fields have no file offset, the mutator
        // edits them through ArchiveBytes (fuzz_archive_fields.cpp, mutateEntryField).
        l.packed_metadata = version >= 6;
        if (index <= size && version < 5) {
            l.index_offset = size_t(index);
            l.entries = (size - l.index_offset) / e::kEntrySize;
        }
        l.valid = true;
        return l;
    }
    Field headerField(uint32_t r) const { return kHeaderFields[r % std::size(kHeaderFields)]; }
    // Entry `pick` chooses, biased to the top of the tree: the root's box and error feed the
    // default camera, the ground height and every selection, level 1 most of the rest.
    Field indexField(uint32_t pick, uint32_t r) const
    {
        if (entries == 0)
            return headerField(r);
        const size_t entry = pick % 3 == 0   ? 0
                             : pick % 3 == 1 ? (pick / 3) % std::min<size_t>(entries, 5)
                                             : (pick / 3) % entries;
        const Field f = kEntryFields[r % std::size(kEntryFields)];
        return {index_offset + entry * e::kEntrySize + f.offset, f.type};
    }
};

// ArchiveBytes::reseal() predates the codec tables region (format v3): its checksum, then the
// header's again, so that a mutated region reaches the reader's checks too.
inline void resealCodecTables(test::ArchiveBytes& a)
{
    std::vector<uint8_t>& b = a.bytes();
    if (b.size() < h::kHeaderSize || a.get<uint32_t>(8) < 3)
        return;
    namespace ct = test::codec_tables_offset;
    const uint64_t offset = a.get<uint64_t>(ct::kOffset);
    const uint32_t size = a.get<uint32_t>(ct::kSize);
    if (offset > b.size() || size > b.size() - offset)
        return;
    a.set<uint32_t>(ct::kCrc, size ? crc32(b.data() + offset, size) : 0);
    a.set<uint32_t>(h::kHeaderCrc, crc32(b.data(), h::kHeaderCrc));
}

template <typename T> T load(const uint8_t* p)
{
    T v;
    std::memcpy(&v, p, sizeof v);
    return v;
}

template <typename T> void store(uint8_t* p, T v)
{
    std::memcpy(p, &v, sizeof v);
}

} // namespace ridge::fuzz
