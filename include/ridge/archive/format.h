#pragma once
// The .ridge archive, format version 6 (version 5: the same with the metadata stored as it
// is; version 4: also with zstd sample-flag bitmaps and the index entries stored as they are;
// version 3: also without per-patch sample flags; version 2: also without the codec tables
// region; version 1: also without validity masks). docs/FORMAT.md is
// the normative description; this header mirrors it. All integers and floats are little-endian,
// IEEE-754.
//
//   [header: 160 bytes][patch blobs][codec tables][metadata: JSON (v6: zstd)][index]
//
// The index holds a 48-byte entry per patch: as they are up to version 4, from version 5 in
// one zstd frame, byte-transposed (packIndex). The metadata JSON is stored as it is up to
// version 5, from version 6 as one zstd frame against a fixed reference (packMetadata).
//
// Compatibility: readers accept every version <= kFormatVersion and reject newer ones;
// writers always write kFormatVersion.
#include "ridge/pyramid/pyramid_geometry.h"

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace ridge::archive {

inline constexpr char kMagic[8] = {'R', 'I', 'D', 'G', 'E', 'A', 'R', 'C'};
inline constexpr uint32_t kFormatVersion = 6;
// The first version whose blobs hold a validity mask after the block errors.
inline constexpr uint32_t kFirstVersionWithValidity = 2;
// The first version with a codec tables region (header bytes 140..155, zero before).
inline constexpr uint32_t kFirstVersionWithCodecTables = 3;
// The first version whose blobs hold sample flags (water, filled) after the validity mask.
inline constexpr uint32_t kFirstVersionWithSampleFlags = 4;
// The first version whose sample-flag bitmaps are context-coded (kind 3) instead of zstd's.
inline constexpr uint32_t kFirstVersionWithContextCodedFlags = 5;
// The first version whose index is one zstd frame of byte-transposed entries.
inline constexpr uint32_t kFirstVersionWithPackedIndex = 5;
// The first version whose metadata is one zstd frame coded against metadataReference().
inline constexpr uint32_t kFirstVersionWithPackedMetadata = 6;
inline constexpr size_t kHeaderSize = 160;
inline constexpr size_t kIndexEntrySize = 48;
// λ stored as this value means "larger than representable: never simplify".
inline constexpr uint16_t kBlockErrorSaturated = 0xffff;
// The largest code: metres(kMaxCode) is the highest height an archive can hold, metres(0) the
// lowest (heights are monotone in the code, height_scale > 0).
inline constexpr double kMaxCode = 65535;

struct Header {
    uint32_t version = kFormatVersion;
    uint32_t width = 0; // valid extent, finest samples
    uint32_t height = 0;
    uint32_t patch_size = 0; // 2^n + 1
    uint32_t level_count = 0;
    uint32_t block_cells = 0;  // tessellation block size in cells, 2^k
    uint32_t block_levels = 0; // D: λ(d) stored for d = 1..D
    uint32_t codec_id = 0;
    uint32_t filter_id = 0;
    double height_scale = 1.0; // metres = height_offset + height_scale * code
    double height_offset = 0.0;
    double spacing_x = 1.0;             // metres between finest samples along x (east)
    double spacing_y = 1.0;             // along y (south)
    double quantization_error = 0.0;    // max |metres(code) - source| over valid samples
    double codec_param[2] = {0.0, 0.0}; // codec specific (unused by lossless/raw)
    uint64_t metadata_offset = 0;
    uint32_t metadata_size = 0;
    uint32_t metadata_crc32 = 0;
    uint64_t index_offset = 0;
    uint32_t index_crc32 = 0;
    // Version 3: the codec's per-archive tables (e.g. progressive v2's entropy tables), after
    // the blobs and before the metadata: codec_tables_offset + codec_tables_size =
    // metadata_offset. Size 0: none (the offset then equals metadata_offset).
    uint64_t codec_tables_offset = 0;
    uint32_t codec_tables_size = 0;
    uint32_t codec_tables_crc32 = 0;

    // Where the patch blobs end: the codec tables (version 3) or the metadata.
    uint64_t patchAreaEnd() const
    {
        return version >= kFirstVersionWithCodecTables ? codec_tables_offset : metadata_offset;
    }
};

// One index entry: where patch (level, x, y) is and what the renderer needs before reading it.
struct PatchRecord {
    uint32_t level = 0;
    uint32_t x = 0;
    uint32_t y = 0;
    uint32_t block_errors_size = 0; // bytes at the start of the blob: zstd frame of λ values
                                    // (then, version 2, the validity mask, version 4 the
                                    // sample flags, then the payload)
    uint64_t offset = 0;            // blob position in the file
    uint32_t size = 0;              // blob size: block errors + codec payload
    uint32_t crc32 = 0;             // CRC-32 of the whole blob
    float min_height = 0.f;         // metres, <= every sample of the patch and of its
                                    // descendants (rounded down): safe for culling
    float max_height = 0.f;         // metres, >= all those samples (rounded up)
    float err_appr = 0.f;           // Err_Appr(P), metres, rounded up
    float err = 0.f;                // Err(P) = Err_Appr(P) + δ_l, metres, rounded up
};

// Byte-exact (de)serialisation. parseHeader returns an empty string on success, otherwise
// what is wrong (bad magic, newer version, checksum), naming the field for values outside
// their documented range: non-zero reserved bytes, height_scale, height_offset and the
// height of code 65535, spacing_x/y, quantization_error, metadata_size (docs/FORMAT.md).
// Geometry, block layout, filter and codec fields are checked by ArchiveReader, which knows
// the codecs.
void serializeHeader(const Header& header, uint8_t out[kHeaderSize]);
std::string parseHeader(const uint8_t in[kHeaderSize], Header& header);
void serializeRecord(const PatchRecord& record, uint8_t out[kIndexEntrySize]);
PatchRecord parseRecord(const uint8_t in[kIndexEntrySize]);

// The index region of an archive of format `version`: the entries (serializeRecord) one after
// the other up to version 4; from version 5 one zstd frame, stating its content size, of the
// same count·48 bytes byte-transposed (byte k of entry i at k·count + i: a field's bytes of
// every entry side by side, where zstd finds the levels, positions and offsets alike).
// A quarter of the bytes on real archives (docs/PERF.md).
std::vector<uint8_t> packIndex(const std::vector<PatchRecord>& records, uint32_t version);
// The count·48 entry bytes of an index region of `size` bytes, as serializeRecord wrote them,
// into `entries`; the problem otherwise (the region is not exactly that, or, version 5, not
// one zstd frame of that content). `count` must already be bounded by the file (the caller
// allocates count·48 bytes).
std::string unpackIndex(const uint8_t* data, size_t size, uint64_t count, uint32_t version,
                        std::vector<uint8_t>& entries);

// The metadata region of an archive of format `version`: the JSON document as it is up to
// version 5; from version 6 one zstd frame, stating its content size, coded with
// metadataReference() as its prefix (a WGS 84 source's 2 KB document packs into about 100
// bytes: the CRS's WKT is most of it, and the reference holds the common ones).
std::vector<uint8_t> packMetadata(const std::string& json, uint32_t version);
// The document of a metadata region of `size` bytes into `json`; the problem otherwise
// (version 6: not exactly one zstd frame stating a content size in [2, kMaxMetadataBytes],
// checked before allocating, or one that does not decompress to it against the reference).
// The document itself is checked by parseArchiveMetadata.
std::string unpackMetadata(const uint8_t* data, size_t size, uint32_t version, std::string& json);
// The metadata reference of format 6 (src/archive/metadata_reference.cpp): fixed bytes that
// are part of the format, never edited.
std::string_view metadataReference();

// Float rounding that never moves a bound inwards: the nearest float <= / >= value.
float floatDown(double value);
float floatUp(double value);

} // namespace ridge::archive
