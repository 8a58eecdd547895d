// libFuzzer target: archives whose checksums are right but whose fields are hostile, fed
// through everything a renderer does on the CPU before it touches GL.
//
// CRC-32 stops accidents, not a buggy writer or an attacker, so this target re-seals every
// input (header, metadata, index and blob checksums recomputed) before opening it: every
// mutation reaches the field checks instead of dying at a checksum. A custom mutator edits
// whole fields of real archives (header, index entries, metadata values: in place, or in the
// document of a packed metadata frame, format 6) with the values that
// break arithmetic: NaN, infinities, zero, negative, huge, off-by-one; and the validity masks
// of the blobs (kind, frame_size, frame bytes). And what the second review found (issue 23),
// changing sizes where they must: metadata values nested up to 100,000 deep and bytes after a
// NUL, whole masks replaced at coarse levels (so that they no longer follow from the finest
// level), codec tables on codecs without them, bytes after a payload's end (a JPEG 2000
// codestream's EOC) and zeroed words inside payloads (a tile-part's Psot).
//
// Then, for archives the reader accepts: the patch quadtree, LOD selection for a handful of
// cameras and ε, slot residency, synchronous patch loading, the streaming fallback cover,
// Ulrich's chunk meshes and the instance records of the draw, all plain C++; and, for small
// ones, `ridge verify` whole (every cross-level check).
// Properties: every failure is a ridge::Error, never a crash, an out-of-bounds access, UB or
// an unbounded allocation; what is selected exists and what is drawn has a valid slot;
// verify reports, never throws.
#include "archive_fields.h"
#include "memory_file.h"
#include "render_cpu_frame.h"

#include "ridge/archive/archive_reader.h"
#include "ridge/core/error.h"
#include "ridge/pipeline/verify.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <string>
#include <vector>

extern "C" size_t LLVMFuzzerMutate(uint8_t* data, size_t size, size_t max_size);

namespace {

using ridge::fuzz::FieldType;

template <typename T> T pick(std::minstd_rand& rng, std::initializer_list<T> values)
{
    return *(values.begin() + rng() % values.size());
}

void mutateFloat(uint8_t* p, FieldType type, std::minstd_rand& rng)
{
    double v = type == FieldType::F64 ? ridge::fuzz::load<double>(p) : ridge::fuzz::load<float>(p);
    switch (rng() % 4) {
    case 0:
        v = pick<double>(rng, {NAN, INFINITY, -INFINITY, 0.0, -0.0, -1.0, 1e-300, 1e-45, 1e30,
                               3.4e38, 1e300, 65535.0, 1e7, -1e7, 32767.5});
        break;
    case 1:
        v = std::nextafter(v, rng() % 2 ? INFINITY : -INFINITY);
        break;
    case 2:
        v *= pick<double>(rng, {-1.0, 2.0, 0.5, 1e6, 1e-6});
        break;
    default:
        v = double(int32_t(rng())) / double(1 + rng() % 1000);
        break;
    }
    if (type == FieldType::F64)
        ridge::fuzz::store<double>(p, v);
    else
        ridge::fuzz::store<float>(p, static_cast<float>(v));
}

void mutateInteger(uint8_t* p, FieldType type, size_t file_size, std::minstd_rand& rng)
{
    const uint64_t v =
        type == FieldType::U64 ? ridge::fuzz::load<uint64_t>(p) : ridge::fuzz::load<uint32_t>(p);
    uint64_t w = 0;
    switch (rng() % 4) {
    case 0:
        w = pick<uint64_t>(rng,
                           {0, 1, 2, 3, 4, 5, 8, 9, 17, 65, 129, 160, 0x7fffffff, 0x80000000u,
                            0xffffffffu, ~uint64_t{0}, file_size, file_size - 1, file_size + 1});
        break;
    case 1:
        w = v + (rng() % 2 ? 1 : -1);
        break;
    case 2:
        w = v * 2 + rng() % 2;
        break;
    default:
        w = rng() % (file_size + 2);
        break;
    }
    if (type == FieldType::U64)
        ridge::fuzz::store<uint64_t>(p, w);
    else
        ridge::fuzz::store<uint32_t>(p, static_cast<uint32_t>(w));
}

// Overwrites one JSON value of a metadata document with a token of another kind or range,
// padded with spaces to the same length (so that, stored as it is before format 6, the layout
// of the file is unchanged).
void mutateMetadataValue(char* data, size_t size, std::minstd_rand& rng)
{
    std::vector<size_t> colons;
    for (size_t k = 0; k < size; ++k)
        if (data[k] == ':')
            colons.push_back(k);
    if (colons.empty())
        return;
    const size_t start = colons[rng() % colons.size()] + 1;
    size_t end = start;
    int depth = 0;
    while (end < size &&
           (depth > 0 || (data[end] != ',' && data[end] != '}' && data[end] != '\n'))) {
        depth += data[end] == '[' || data[end] == '{';
        depth -= data[end] == ']' || data[end] == '}';
        ++end;
    }
    const std::string token = pick<std::string>(rng, {"null",
                                                      "true",
                                                      "0",
                                                      "-1",
                                                      "1e999",
                                                      "-1e999",
                                                      "NaN",
                                                      "1.5",
                                                      "\"\"",
                                                      "\"x\"",
                                                      "[]",
                                                      "{}",
                                                      "65",
                                                      "129",
                                                      "4294967296",
                                                      "[0,0,0,0,0,0]",
                                                      "[1e308,1,0,1,0,-1]",
                                                      "\"raw\"",
                                                      "\"lossless\"",
                                                      "\"neville\"",
                                                      "2"});
    if (token.size() > end - start)
        return;
    std::memset(data + start, ' ', end - start);
    std::memcpy(data + start, token.data(), token.size());
}

// From format 6 the metadata is a zstd frame: its values are edited in the document, which
// is then packed again (the region's size changes).
void mutatePackedMetadataValue(ridge::test::ArchiveBytes& a, std::minstd_rand& rng)
{
    std::string text = a.metadata();
    mutateMetadataValue(text.data(), text.size(), rng);
    a.setMetadata(text);
}

// Edits the validity mask (format v2) of one patch, which starts after its block errors:
// the kind byte, the frame_size word, or a byte of the zstd frame (reseal() then gets the
// edit past the blob's CRC, so the mask's own checks must catch it).
void mutateValidityMask(uint8_t* data, size_t size, const ridge::fuzz::ArchiveLayout& layout,
                        std::minstd_rand& rng)
{
    if (layout.entries == 0)
        return;
    namespace e = ridge::test::entry_offset;
    const size_t entry = layout.index_offset + (rng() % layout.entries) * e::kEntrySize;
    if (entry + e::kEntrySize > size)
        return;
    const uint64_t offset = ridge::fuzz::load<uint64_t>(data + entry + e::kOffset);
    const uint32_t blob = ridge::fuzz::load<uint32_t>(data + entry + e::kSize);
    const uint32_t block_errors = ridge::fuzz::load<uint32_t>(data + entry + e::kBlockErrorsSize);
    if (offset > size || blob > size - offset || block_errors >= blob)
        return;
    uint8_t* mask = data + offset + block_errors;
    const size_t room = blob - block_errors;
    switch (rng() % 3) {
    case 0:
        mask[0] = pick<uint8_t>(rng, {0, 1, 2, 3, 255});
        break;
    case 1:
        if (room >= 5) {
            const uint32_t v = ridge::fuzz::load<uint32_t>(mask + 1);
            ridge::fuzz::store<uint32_t>(
                mask + 1, pick<uint32_t>(rng, {0, 1, v - 1, v + 1, uint32_t(room), 0xffffffffu}));
        }
        break;
    default: {
        const size_t at = rng() % std::min<size_t>(room, 64);
        mask[at] ^= uint8_t(1u << (rng() % 8));
        break;
    }
    }
}

namespace e = ridge::test::entry_offset;

// Metadata that breaks the document's bounds: a value nested `depth` deep (the parser must
// refuse past 32 before anything recurses), or valid JSON followed by a NUL and bytes.
void mutateMetadataShape(ridge::test::ArchiveBytes& a, std::minstd_rand& rng)
{
    std::string text = a.metadata();
    if (rng() % 3 == 0) {
        text += std::string(1, '\0') + pick<std::string>(rng, {"", "x", "{}", "\0\0", "{\"a\":1}"});
    } else {
        const size_t close = text.rfind('}');
        if (close == std::string::npos)
            return;
        const size_t depth = pick<size_t>(rng, {2, 31, 32, 33, 64, 1000, 100000});
        const std::string open = rng() % 2 ? "[" : "{\"k\":";
        std::string value;
        for (size_t k = 0; k < depth; ++k)
            value += open;
        value += "1";
        for (size_t k = 0; k < depth; ++k)
            value += open == "[" ? "]" : "}";
        text.insert(close, ",\"deep\":" + value);
    }
    a.setMetadata(text);
}

// One index entry, biased to the coarse levels (the first entries), whose blob lies in the
// file with its block errors inside it; -1 when there is none.
int64_t pickBlob(const ridge::test::ArchiveBytes& a, std::minstd_rand& rng)
{
    const size_t entries = a.entryCount();
    if (entries == 0)
        return -1;
    const size_t i = rng() % 2 ? rng() % std::min<size_t>(entries, 7) : rng() % entries;
    const uint64_t offset = a.entry<uint64_t>(i, e::kOffset);
    const uint32_t size = a.entry<uint32_t>(i, e::kSize);
    const uint32_t block_errors = a.entry<uint32_t>(i, e::kBlockErrorsSize);
    const size_t file = const_cast<ridge::test::ArchiveBytes&>(a).bytes().size();
    if (offset > file || size > file - offset || block_errors >= size)
        return -1;
    return int64_t(i);
}

// A whole validity mask replaced by another kind (its size changes): coarse masks that no
// longer follow from the finest level, a bitmap turned into "all valid".
void mutateWholeMask(ridge::test::ArchiveBytes& a, std::minstd_rand& rng)
{
    const int64_t i = pickBlob(a, rng);
    if (i < 0)
        return;
    const std::vector<uint8_t> blob = ridge::test::blobOf(a, size_t(i));
    const size_t at = a.entry<uint32_t>(size_t(i), e::kBlockErrorsSize);
    uint32_t frame = 0;
    if (blob[at] == 2 && blob.size() - at >= 5)
        std::memcpy(&frame, blob.data() + at + 1, 4);
    const size_t mask = blob[at] == 2 ? 5 + size_t(frame) : 1;
    if (mask >= blob.size() - at)
        return;
    ridge::test::replaceBlobBytes(a, size_t(i), at, at + mask,
                                  {pick<uint8_t>(rng, {0, 1, 0, 1, 2})});
}

// Bytes after a payload's end (after a JPEG 2000 codestream's EOC marker, typically), or a
// zeroed 32-bit word inside it (a tile-part's Psot, a length field).
void mutatePayloadEnd(ridge::test::ArchiveBytes& a, std::minstd_rand& rng)
{
    const int64_t i = pickBlob(a, rng);
    if (i < 0)
        return;
    const uint32_t size = a.entry<uint32_t>(size_t(i), e::kSize);
    if (rng() % 2) {
        ridge::test::replaceBlobBytes(
            a, size_t(i), size, size,
            pick<std::vector<uint8_t>>(
                rng,
                {{0}, {0xFF, 0xD9}, {0xFF, 0xD9, 0xFF, 0xD9}, {0x2A, 0x2A, 0x2A, 0x2A, 0x2A}}));
    } else if (size >= 8) {
        const size_t at = size_t(rng() % (size - 4));
        ridge::test::replaceBlobBytes(a, size_t(i), at, at + 4, {0, 0, 0, 0});
    }
}

// The codec tables region: bytes where the codec has none, a well-formed header with junk,
// or nothing.
void mutateCodecTables(ridge::test::ArchiveBytes& a, std::minstd_rand& rng)
{
    if (a.get<uint32_t>(8) < 3)
        return;
    namespace ct = ridge::test::codec_tables_offset;
    const uint64_t offset = a.get<uint64_t>(ct::kOffset);
    const uint32_t size = a.get<uint32_t>(ct::kSize);
    if (offset > a.bytes().size() || size > a.bytes().size() - offset)
        return;
    std::vector<uint8_t> tables;
    switch (rng() % 3) {
    case 0:
        break;
    case 1:
        tables = {'T', 1, uint8_t(a.get<uint32_t>(28)), 0};
        for (uint32_t k = rng() % 64; k > 0; --k)
            tables.push_back(uint8_t(rng() % 4));
        break;
    default:
        for (uint32_t k = 1 + rng() % 32; k > 0; --k)
            tables.push_back(uint8_t(rng()));
        break;
    }
    ridge::test::setCodecTables(a, tables);
}

// One field of a packed index (format 5), through ArchiveBytes, which packs it again: the
// index's size changes with its content.
void mutateEntryField(ridge::test::ArchiveBytes& a, std::minstd_rand& rng)
{
    const size_t entries = a.entryCount();
    if (!a.packedIndex() || entries == 0)
        return;
    const uint32_t pick = rng();
    const size_t entry = pick % 3 == 0   ? 0
                         : pick % 3 == 1 ? (pick / 3) % std::min<size_t>(entries, 5)
                                         : (pick / 3) % entries;
    const ridge::fuzz::Field f =
        ridge::fuzz::kEntryFields[rng() % std::size(ridge::fuzz::kEntryFields)];
    uint8_t value[8] = {};
    if (f.type == FieldType::U64) {
        ridge::fuzz::store(value, a.entry<uint64_t>(entry, f.offset));
        mutateInteger(value, f.type, a.bytes().size(), rng);
        a.setEntry(entry, f.offset, ridge::fuzz::load<uint64_t>(value));
    } else if (f.type == FieldType::U32) {
        ridge::fuzz::store(value, a.entry<uint32_t>(entry, f.offset));
        mutateInteger(value, f.type, a.bytes().size(), rng);
        a.setEntry(entry, f.offset, ridge::fuzz::load<uint32_t>(value));
    } else {
        ridge::fuzz::store(value, a.entry<float>(entry, f.offset));
        mutateFloat(value, f.type, rng);
        a.setEntry(entry, f.offset, ridge::fuzz::load<float>(value));
    }
    a.pack();
}

// Applies one of the mutations that change the file's size; false when none applied.
bool mutateShape(uint8_t* data, size_t& size, size_t max_size, std::minstd_rand& rng)
{
    try {
        ridge::test::ArchiveBytes a(std::vector<uint8_t>(data, data + size));
        if (a.packedIndex() && rng() % 2 == 0) {
            mutateEntryField(a, rng);
        } else {
            switch (rng() % 4) {
            case 0:
                if (a.packedMetadata() && rng() % 2)
                    mutatePackedMetadataValue(a, rng);
                else
                    mutateMetadataShape(a, rng);
                break;
            case 1:
                mutateWholeMask(a, rng);
                break;
            case 2:
                mutatePayloadEnd(a, rng);
                break;
            default:
                mutateCodecTables(a, rng);
                break;
            }
        }
        a.pack(); // a packed index's moved offsets
        if (a.bytes().size() > max_size)
            return false;
        std::memcpy(data, a.bytes().data(), a.bytes().size());
        size = a.bytes().size();
        return true;
    } catch (const std::exception&) { // offsets the header or index made up: no edit
        return false;
    }
}

} // namespace

extern "C" size_t LLVMFuzzerCustomMutator(uint8_t* data, size_t size, size_t max_size,
                                          unsigned int seed)
{
    std::minstd_rand rng(seed);
    const ridge::fuzz::ArchiveLayout layout = ridge::fuzz::ArchiveLayout::of(data, size);
    if (!layout.valid || rng() % 4 == 0)
        return LLVMFuzzerMutate(data, size, max_size); // bytes too: truncations, insertions
    if (rng() % 4 == 0 && mutateShape(data, size, max_size, rng))
        return size;
    const int mutations = 1 + int(rng() % 3);
    for (int m = 0; m < mutations; ++m) {
        const uint32_t what = rng() % 8;
        if (what == 0 && layout.metadata.size > 0 && !layout.packed_metadata) {
            mutateMetadataValue(reinterpret_cast<char*>(data) + layout.metadata.offset,
                                layout.metadata.size, rng);
            continue;
        }
        if (what == 1) {
            mutateValidityMask(data, size, layout, rng);
            continue;
        }
        const ridge::fuzz::Field f =
            what < 4 ? layout.headerField(rng()) : layout.indexField(rng(), rng());
        if (f.offset + ridge::fuzz::fieldBytes(f.type) > size)
            continue;
        if (f.type == FieldType::F32 || f.type == FieldType::F64)
            mutateFloat(data + f.offset, f.type, rng);
        else
            mutateInteger(data + f.offset, f.type, size, rng);
    }
    return size;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    ridge::test::ArchiveBytes archive(std::vector<uint8_t>(data, data + size));
    if (size >= ridge::test::header_offset::kHeaderSize) {
        archive.reseal();
        ridge::fuzz::resealCodecTables(archive);
    }
    static const ridge::fuzz::MemoryFile file; // the reader needs a path, the disk need not
    file.write(archive.bytes().data(), archive.bytes().size());
    try {
        const ridge::archive::ArchiveReader reader(file.path());
        const int n = reader.geometry().patchSize();
        if (reader.geometry().patchCount() > 4096 || n > 257)
            return 0; // valid but too big to be worth walking in a fuzzing loop
        ridge::fuzz::runCpuFrames(reader);
        for (int64_t i = 0; i < reader.geometry().patchCount(); ++i) {
            try {
                reader.readValidity(reader.geometry().patchAt(i));
            } catch (const ridge::Error&) {
            }
        }
        // verify whole: every decode, and the checks across levels (masks, Err_Int). On the
        // smaller archives only (up to the 99 patches of a 33-sample Everest): a whole verify
        // under the sanitizers costs about a second on the larger seeds.
        if (reader.geometry().patchCount() <= 128 && n <= 65)
            (void)ridge::verifyArchive(file.path(), ridge::VerifyOptions{});
    } catch (const ridge::Error&) {
    }
    return 0;
}
