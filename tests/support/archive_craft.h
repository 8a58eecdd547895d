#pragma once
// Edits of a .ridge archive that change a region's size (archive_bytes.h keeps sizes except
// for the metadata): a blob's bytes replaced by shorter or longer ones, the codec tables
// region replaced, every later offset moved to follow. Offsets from docs/FORMAT.md, as in
// archive_bytes.h; the caller reseals. Blob layout: [block errors][validity mask][...][payload]
// (format v2 and later; whatever a later version puts between the mask and the payload
// moves with the payload).
#include "archive_bytes.h"

#include "ridge/archive/archive_reader.h"
#include "ridge/core/error.h"

#include <cstdint>
#include <cstring>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace ridge::test {

namespace codec_tables_offset {
inline constexpr size_t kOffset = 140, kSize = 148, kCrc = 152;
} // namespace codec_tables_offset

// Replaces bytes [begin, end) of index entry `entry`'s blob (offsets within the blob) with
// `replacement`; later blobs, the codec tables, the metadata and the index move accordingly.
inline void replaceBlobBytes(ArchiveBytes& a, size_t entry, size_t begin, size_t end,
                             const std::vector<uint8_t>& replacement)
{
    const uint64_t offset = a.entry<uint64_t>(entry, entry_offset::kOffset);
    const uint32_t size = a.entry<uint32_t>(entry, entry_offset::kSize);
    if (begin > end || end > size)
        throw std::out_of_range("replaceBlobBytes: range outside the blob");
    const int64_t delta = int64_t(replacement.size()) - int64_t(end - begin);
    // Offsets first (the index moves with the bytes, so rewrite it before moving anything).
    for (size_t i = 0; i < a.entryCount(); ++i) {
        const uint64_t o = a.entry<uint64_t>(i, entry_offset::kOffset);
        if (o > offset)
            a.setEntry<uint64_t>(i, entry_offset::kOffset, uint64_t(int64_t(o) + delta));
    }
    a.setEntry<uint32_t>(entry, entry_offset::kSize, uint32_t(int64_t(size) + delta));
    namespace ho = header_offset;
    for (const size_t field : {ho::kMetadataOffset, ho::kIndexOffset})
        a.set<uint64_t>(field, uint64_t(int64_t(a.get<uint64_t>(field)) + delta));
    if (a.get<uint32_t>(8) >= 3)
        a.set<uint64_t>(codec_tables_offset::kOffset,
                        uint64_t(int64_t(a.get<uint64_t>(codec_tables_offset::kOffset)) + delta));
    std::vector<uint8_t>& b = a.bytes();
    const auto at = b.begin() + std::ptrdiff_t(offset + begin);
    b.erase(at, at + std::ptrdiff_t(end - begin));
    b.insert(b.begin() + std::ptrdiff_t(offset + begin), replacement.begin(), replacement.end());
}

// Bytes of the validity mask that starts at blob byte `at` (docs/FORMAT.md, "Validity mask").
inline size_t validityMaskSize(const std::vector<uint8_t>& blob, size_t at)
{
    if (blob.at(at) != 2)
        return 1;
    uint32_t frame = 0;
    std::memcpy(&frame, blob.data() + at + 1, 4);
    return 5 + frame;
}

// The blob of index entry `entry`.
inline std::vector<uint8_t> blobOf(const ArchiveBytes& a, size_t entry)
{
    const uint64_t offset = a.entry<uint64_t>(entry, entry_offset::kOffset);
    const uint32_t size = a.entry<uint32_t>(entry, entry_offset::kSize);
    const std::vector<uint8_t>& b = const_cast<ArchiveBytes&>(a).bytes();
    return {b.begin() + std::ptrdiff_t(offset), b.begin() + std::ptrdiff_t(offset + size)};
}

// Replaces the codec tables region (format v3) with `tables` and its checksum; the metadata
// and the index move. Reseal afterwards for the header's checksum.
inline void setCodecTables(ArchiveBytes& a, const std::vector<uint8_t>& tables)
{
    namespace ct = codec_tables_offset;
    const uint64_t offset = a.get<uint64_t>(ct::kOffset);
    const uint32_t size = a.get<uint32_t>(ct::kSize);
    const int64_t delta = int64_t(tables.size()) - int64_t(size);
    std::vector<uint8_t>& b = a.bytes();
    b.erase(b.begin() + std::ptrdiff_t(offset), b.begin() + std::ptrdiff_t(offset + size));
    b.insert(b.begin() + std::ptrdiff_t(offset), tables.begin(), tables.end());
    a.set<uint32_t>(ct::kSize, uint32_t(tables.size()));
    a.set<uint32_t>(ct::kCrc, tables.empty() ? 0 : crc32(tables.data(), tables.size()));
    namespace ho = header_offset;
    for (const size_t field : {ho::kMetadataOffset, ho::kIndexOffset})
        a.set<uint64_t>(field, uint64_t(int64_t(a.get<uint64_t>(field)) + delta));
}

// Copies `archive`, applies `edit`, reseals every checksum, saves the result as `crafted` and
// opens it. Returns the reader's message, or "" when it opened.
inline std::string openEdited(const std::string& archive, const std::string& crafted,
                              const std::function<void(ArchiveBytes&)>& edit)
{
    ArchiveBytes bytes(archive);
    edit(bytes);
    bytes.reseal();
    bytes.save(crafted);
    try {
        const archive::ArchiveReader reader(crafted);
        return "";
    } catch (const Error& e) {
        return e.what();
    }
}

} // namespace ridge::test
