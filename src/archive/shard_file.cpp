#include "ridge/archive/shard_file.h"

#include "ridge/core/atomic_output.h"
#include "ridge/core/crc32.h"
#include "ridge/core/error.h"
#include "ridge/core/file_io.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace ridge::archive {

namespace {

constexpr char kMagic[8] = {'R', 'I', 'D', 'G', 'E', 'S', 'H', 'D'};
constexpr uint32_t kVersion = 1;
constexpr size_t kHeaderSize = 64;
// tag u32, flags u32 (bit 0: crc32 holds the section's CRC-32), crc32 u32, reserved u32,
// offset u64, size u64.
constexpr size_t kDirectoryEntrySize = 32;
constexpr uint32_t kHasCrc = 1;
// The most sections a file may have (a reader refuses more before allocating).
constexpr uint32_t kMaxSections = 64;

void put(uint8_t* at, uint64_t v, int bytes)
{
    for (int b = 0; b < bytes; ++b)
        at[b] = static_cast<uint8_t>(v >> (8 * b));
}

uint64_t get(const uint8_t* at, int bytes)
{
    uint64_t v = 0;
    for (int b = 0; b < bytes; ++b)
        v |= uint64_t{at[b]} << (8 * b);
    return v;
}

bool knownKind(uint32_t kind)
{
    return kind >= 1 && kind <= 4;
}

std::string tagName(uint32_t tag)
{
    std::string name;
    for (int b = 0; b < 4; ++b)
        name += static_cast<char>(tag >> (8 * b));
    return name;
}

} // namespace

const char* shardFileKindName(ShardFileKind kind)
{
    switch (kind) {
    case ShardFileKind::Summary:
        return "summary";
    case ShardFileKind::Observations:
        return "observations";
    case ShardFileKind::Top:
        return "top";
    case ShardFileKind::Segment:
        return "segment";
    }
    return "unknown";
}

struct ShardFileWriter::Impl {
    AtomicOutput output;
    ShardFileHeader header;
    std::vector<uint8_t> directory;
    uint32_t sections = 0;
    uint32_t open_tag = 0;
    bool open = false;
    explicit Impl(const std::string& path) : output(path) {}
};

ShardFileWriter::ShardFileWriter(const std::string& path, const ShardFileHeader& header)
    : impl_(new Impl(path))
{
    impl_->header = header;
    const uint8_t zeros[kHeaderSize] = {};
    writeAll(impl_->output.fd(), zeros, kHeaderSize, path);
    position_ = kHeaderSize;
}

ShardFileWriter::~ShardFileWriter()
{
    delete impl_;
}

void ShardFileWriter::addSection(uint32_t tag, const void* data, size_t size)
{
    beginSection(tag);
    append(data, size);
    uint8_t* entry = impl_->directory.data() + impl_->directory.size() - kDirectoryEntrySize;
    put(entry + 4, kHasCrc, 4);
    put(entry + 8, crc32(data, size), 4);
    impl_->open = false;
    put(entry + 24, size, 8);
}

void ShardFileWriter::beginSection(uint32_t tag)
{
    if (impl_->open || impl_->sections == kMaxSections)
        throw Error(impl_->output.finalPath() + ": internal error: shard file sections");
    impl_->open = true;
    impl_->open_tag = tag;
    section_start_ = position_;
    uint8_t entry[kDirectoryEntrySize] = {};
    put(entry, tag, 4);
    put(entry + 16, position_, 8);
    impl_->directory.insert(impl_->directory.end(), entry, entry + kDirectoryEntrySize);
    ++impl_->sections;
}

void ShardFileWriter::append(const void* data, size_t size)
{
    if (!impl_->open)
        throw Error(impl_->output.finalPath() + ": internal error: no open section");
    writeAll(impl_->output.fd(), data, size, impl_->output.finalPath());
    position_ += size;
}

void ShardFileWriter::endSection()
{
    uint8_t* entry = impl_->directory.data() + impl_->directory.size() - kDirectoryEntrySize;
    put(entry + 24, position_ - section_start_, 8);
    impl_->open = false;
}

void ShardFileWriter::finish()
{
    if (impl_->open)
        throw Error(impl_->output.finalPath() + ": internal error: a section is still open");
    const uint64_t directory_offset = position_;
    writeAll(impl_->output.fd(), impl_->directory.data(), impl_->directory.size(),
             impl_->output.finalPath());
    position_ += impl_->directory.size();
    uint8_t h[kHeaderSize] = {};
    std::memcpy(h, kMagic, 8);
    put(h + 8, kVersion, 4);
    put(h + 12, static_cast<uint32_t>(impl_->header.kind), 4);
    put(h + 16, impl_->header.layout_hash, 8);
    put(h + 24, static_cast<uint64_t>(impl_->header.shard), 8);
    put(h + 32, impl_->header.key, 8);
    put(h + 40, impl_->sections, 4);
    put(h + 48, directory_offset, 8);
    put(h + 56, crc32(impl_->directory.data(), impl_->directory.size()), 4);
    put(h + 60, crc32(h, 60), 4);
    writeAllAt(impl_->output.fd(), h, kHeaderSize, 0, impl_->output.finalPath());
    impl_->output.commit();
}

ShardFileReader::ShardFileReader(const std::string& path) : path_(path)
{
    fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd_ < 0)
        throw Error(path + ": cannot open: " + std::strerror(errno));
    struct stat st {};
    if (::fstat(fd_, &st) != 0 || !S_ISREG(st.st_mode)) {
        ::close(fd_);
        throw Error(path + ": not a regular file");
    }
    const uint64_t file_size = static_cast<uint64_t>(st.st_size);
    auto fail = [&](const std::string& what) {
        ::close(fd_);
        fd_ = -1;
        throw Error(path + ": not a ridge shard file: " + what);
    };
    if (file_size < kHeaderSize)
        fail(std::to_string(file_size) + " bytes, shorter than the 64-byte header");
    uint8_t h[kHeaderSize];
    readAllAt(fd_, h, kHeaderSize, 0, path);
    if (std::memcmp(h, kMagic, 8) != 0)
        fail("it does not start with RIDGESHD");
    if (get(h + 60, 4) != crc32(h, 60))
        fail("header CRC-32 mismatch");
    if (get(h + 8, 4) != kVersion)
        fail("version " + std::to_string(get(h + 8, 4)) + " (this ridge reads 1)");
    if (!knownKind(static_cast<uint32_t>(get(h + 12, 4))))
        fail("kind " + std::to_string(get(h + 12, 4)) + " is not 1..4");
    header_.kind = static_cast<ShardFileKind>(get(h + 12, 4));
    header_.layout_hash = get(h + 16, 8);
    header_.shard = static_cast<int64_t>(get(h + 24, 8));
    header_.key = get(h + 32, 8);
    const uint64_t count = get(h + 40, 4), directory_offset = get(h + 48, 8);
    if (count > kMaxSections)
        fail(std::to_string(count) + " sections (at most 64)");
    if (get(h + 44, 4) != 0)
        fail("reserved header bytes 44..47 are not 0");
    if (directory_offset < kHeaderSize ||
        directory_offset + count * kDirectoryEntrySize != file_size)
        fail("the section directory does not end the file (truncated or extended?)");
    std::vector<uint8_t> directory(count * kDirectoryEntrySize);
    readAllAt(fd_, directory.data(), directory.size(), directory_offset, path);
    if (get(h + 56, 4) != crc32(directory.data(), directory.size()))
        fail("section directory CRC-32 mismatch");
    for (uint64_t k = 0; k < count; ++k) {
        const uint8_t* e = directory.data() + k * kDirectoryEntrySize;
        const uint64_t flags = get(e + 4, 4);
        const Section s{static_cast<uint32_t>(get(e, 4)), (flags & kHasCrc) != 0,
                        static_cast<uint32_t>(get(e + 8, 4)), get(e + 16, 8), get(e + 24, 8)};
        if ((flags & ~uint64_t{kHasCrc}) != 0 || get(e + 12, 4) != 0 ||
            (!s.has_crc && s.crc32 != 0))
            fail("section " + tagName(s.tag) + " has unknown flags or reserved bytes set");
        if (s.offset < kHeaderSize || s.offset > directory_offset ||
            s.size > directory_offset - s.offset)
            fail("section " + tagName(s.tag) + " lies outside the data");
        for (const Section& o : sections_)
            if (o.tag == s.tag)
                fail("section " + tagName(s.tag) + " twice");
            else if (s.offset < o.offset + o.size && o.offset < s.offset + s.size)
                fail("sections " + tagName(o.tag) + " and " + tagName(s.tag) + " overlap");
        sections_.push_back(s);
    }
}

ShardFileReader::~ShardFileReader()
{
    if (fd_ >= 0)
        ::close(fd_);
}

void ShardFileReader::expect(ShardFileKind kind, uint64_t layout_hash, int64_t shard) const
{
    const auto who = [](ShardFileKind k, int64_t s) {
        return std::string(shardFileKindName(k)) + (s < 0 ? std::string(" file of the coordinator")
                                                          : " file of shard " + std::to_string(s));
    };
    if (header_.kind != kind || header_.shard != shard)
        throw Error(path_ + ": is a " + who(header_.kind, header_.shard) + ", not a " +
                    who(kind, shard));
    if (header_.layout_hash != layout_hash)
        throw Error(path_ + ": the " + who(kind, shard) + " was made for another plan");
}

const ShardFileReader::Section& ShardFileReader::section(uint32_t tag) const
{
    for (const Section& s : sections_)
        if (s.tag == tag)
            return s;
    throw Error(path_ + ": has no " + tagName(tag) + " section");
}

bool ShardFileReader::has(uint32_t tag) const
{
    return std::any_of(sections_.begin(), sections_.end(),
                       [&](const Section& s) { return s.tag == tag; });
}

std::vector<uint8_t> ShardFileReader::read(uint32_t tag, uint64_t max_size) const
{
    const Section& s = section(tag);
    if (s.size > max_size)
        throw Error(path_ + ": section " + tagName(tag) + " has " + std::to_string(s.size) +
                    " bytes, more than the " + std::to_string(max_size) + " it can hold");
    std::vector<uint8_t> bytes(s.size);
    readAllAt(fd_, bytes.data(), bytes.size(), s.offset, path_);
    if (!s.has_crc || crc32(bytes.data(), bytes.size()) != s.crc32)
        throw Error(path_ + ": section " + tagName(tag) + " CRC-32 mismatch");
    return bytes;
}

uint64_t ShardFileReader::sectionSize(uint32_t tag) const
{
    return section(tag).size;
}

void ShardFileReader::readAt(uint32_t tag, uint64_t offset, void* data, size_t size) const
{
    const Section& s = section(tag);
    if (offset > s.size || size > s.size - offset)
        throw Error(path_ + ": bytes " + std::to_string(offset) + "+" + std::to_string(size) +
                    " lie outside section " + tagName(tag));
    readAllAt(fd_, data, size, s.offset + offset, path_);
}

bool shardFileMatches(const std::string& path, const ShardFileHeader& header)
{
    try {
        const ShardFileReader reader(path);
        const ShardFileHeader& h = reader.header();
        return h.kind == header.kind && h.layout_hash == header.layout_hash &&
               h.shard == header.shard && h.key == header.key;
    } catch (const Error&) {
        return false;
    }
}

} // namespace ridge::archive
