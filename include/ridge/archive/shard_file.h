#pragma once
// The files a sharded build passes between its steps (pipeline/shard.h; docs/FORMAT.md,
// "Shard files"): a shard's summary and training observations, the coordinator's top file,
// a shard's segment. One container: a 64-byte header naming the kind, the plan layout, the
// shard and the key of the inputs the file was made from, then tagged sections, then a
// directory of them. Every section but a segment's blobs (each checked by its record's
// CRC-32 when copied) carries a CRC-32 checked on read.
#include <cstdint>
#include <string>
#include <vector>

namespace ridge::archive {

enum class ShardFileKind : uint32_t { Summary = 1, Observations = 2, Top = 3, Segment = 4 };
const char* shardFileKindName(ShardFileKind kind);

constexpr uint32_t shardTag(const char (&name)[5])
{
    return uint32_t(uint8_t(name[0])) | uint32_t(uint8_t(name[1])) << 8 |
           uint32_t(uint8_t(name[2])) << 16 | uint32_t(uint8_t(name[3])) << 24;
}

struct ShardFileHeader {
    ShardFileKind kind = ShardFileKind::Summary;
    uint64_t layout_hash = 0; // the plan's layout (options, geometry, shards)
    int64_t shard = -1;       // the shard id; −1: the coordinator's
    uint64_t key = 0;         // hash of the inputs the file was made from
};

// Writes sections in order, then the directory and the header; atomic (nothing at the path
// until finish(), which publishes it).
class ShardFileWriter {
  public:
    ShardFileWriter(const std::string& path, const ShardFileHeader& header);
    ~ShardFileWriter();
    ShardFileWriter(const ShardFileWriter&) = delete;
    ShardFileWriter& operator=(const ShardFileWriter&) = delete;

    void addSection(uint32_t tag, const void* data, size_t size);
    void addSection(uint32_t tag, const std::vector<uint8_t>& bytes)
    {
        addSection(tag, bytes.data(), bytes.size());
    }
    // A section written in pieces (a segment's blobs), without a section CRC.
    void beginSection(uint32_t tag);
    void append(const void* data, size_t size);
    void endSection();
    // Offset of the next byte append() writes, from the open section's start.
    uint64_t sectionPosition() const { return position_ - section_start_; }

    void finish();
    uint64_t bytesWritten() const { return position_; }

  private:
    struct Impl;
    Impl* impl_;
    uint64_t position_ = 0;
    uint64_t section_start_ = 0;
};

// Opens and validates a shard file: header (magic, version, CRC, kind), directory (CRC, every
// section inside the file, none overlapping, no tag twice). Throws ridge::Error naming the
// path and the field.
class ShardFileReader {
  public:
    explicit ShardFileReader(const std::string& path);
    ~ShardFileReader();
    ShardFileReader(const ShardFileReader&) = delete;
    ShardFileReader& operator=(const ShardFileReader&) = delete;

    const std::string& path() const { return path_; }
    const ShardFileHeader& header() const { return header_; }
    // Throws Error("PATH: is a KIND file of shard S, not ...") unless the header matches.
    void expect(ShardFileKind kind, uint64_t layout_hash, int64_t shard) const;

    bool has(uint32_t tag) const;
    // A whole section, its CRC checked; at most `max_size` bytes (a larger one is refused).
    std::vector<uint8_t> read(uint32_t tag, uint64_t max_size) const;
    // Where a section lies, for reading it in pieces (readAt); no CRC check.
    uint64_t sectionSize(uint32_t tag) const;
    void readAt(uint32_t tag, uint64_t offset, void* data, size_t size) const;

  private:
    struct Section {
        uint32_t tag;
        bool has_crc;
        uint32_t crc32;
        uint64_t offset;
        uint64_t size;
    };
    const Section& section(uint32_t tag) const;

    std::string path_;
    int fd_ = -1;
    ShardFileHeader header_;
    std::vector<Section> sections_;
};

// Whether `path` is a shard file of `header`'s kind, layout, shard and key, for a step that
// skips work whose inputs are unchanged. Never throws: anything unreadable is "no".
bool shardFileMatches(const std::string& path, const ShardFileHeader& header);

} // namespace ridge::archive
