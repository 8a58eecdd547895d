#pragma once
// Sequential writer of a .ridge archive. Atomic: nothing appears at the output path until
// finish() succeeds; destroying an unfinished writer removes its temporary file.
#include "ridge/archive/format.h"
#include "ridge/core/atomic_output.h"

#include <cstdio>
#include <string>
#include <vector>

namespace ridge::archive {

class ArchiveWriter {
  public:
    // `header` must have geometry, codec and quantization fields set; offsets and checksums
    // are filled in by the writer. Throws ridge::Error when the file cannot be created.
    ArchiveWriter(const std::string& path, const Header& header);
    ~ArchiveWriter();
    ArchiveWriter(const ArchiveWriter&) = delete;
    ArchiveWriter& operator=(const ArchiveWriter&) = delete;

    // Appends a patch blob (block_errors ++ validity ++ sample flags ++ payload), in any
    // order; each patch exactly once. `record` carries level/x/y and the bounds; offset, size
    // and crc32 are set here. This form stores the all-valid mask and no sample flags
    // (archive/validity_storage.h, sample_flags_storage.h); the other stores `validity`
    // (packValidity's bytes) and `sample_flags` (packSampleFlags') before the payload.
    void writePatch(PatchRecord record, const std::vector<uint8_t>& block_errors,
                    const uint8_t* payload, size_t payload_size);
    void writePatch(PatchRecord record, const std::vector<uint8_t>& block_errors,
                    const std::vector<uint8_t>& validity, const std::vector<uint8_t>& sample_flags,
                    const uint8_t* payload, size_t payload_size);

    // Appends a blob already sealed elsewhere (a shard segment's, pipeline/shard.h): `record`
    // carries its size, block_errors_size and CRC-32 (of `blob`, which the caller checked);
    // the offset is set here.
    void copyPatch(PatchRecord record, const uint8_t* blob);

    // The codec tables region (HeightCodec::storeTables), written by finish() after the
    // blobs; empty = none.
    void setCodecTables(std::vector<uint8_t> tables) { codec_tables_ = std::move(tables); }

    // Writes the codec tables, the metadata, the index and the final header, then publishes the
    // file atomically. Throws ridge::Error when a patch is missing.
    void finish(const std::string& metadata_json);

    uint64_t bytesWritten() const { return position_; }

  private:
    void write(const void* data, size_t size);

    AtomicOutput output_;
    std::FILE* file_ = nullptr;
    Header header_;
    PyramidGeometry geometry_;
    std::vector<PatchRecord> records_;
    std::vector<uint8_t> codec_tables_;
    std::vector<bool> written_;
    int64_t written_count_ = 0;
    uint64_t position_ = 0;
};

} // namespace ridge::archive
