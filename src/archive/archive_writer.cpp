#include "ridge/archive/archive_writer.h"

#include "ridge/archive/archive_metadata.h"
#include "ridge/archive/sample_flags_storage.h"
#include "ridge/archive/validity_storage.h"
#include "ridge/core/crc32.h"
#include "ridge/core/error.h"

#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <unistd.h>

namespace ridge::archive {

namespace {

// Writers always write the current version (docs/FORMAT.md, "Compatibility").
Header withCurrentVersion(Header header)
{
    header.version = kFormatVersion;
    return header;
}

} // namespace

ArchiveWriter::ArchiveWriter(const std::string& path, const Header& header)
    : output_(path), header_(withCurrentVersion(header)),
      geometry_(PyramidGeometry::fromStored(header.width, header.height, header.patch_size,
                                            header.level_count))
{
    // Through the AtomicOutput's own descriptor, never by reopening a name. A duplicate, so
    // that fclose (which closes it) leaves the AtomicOutput's lock and descriptor alone.
    const int fd = ::fcntl(output_.fd(), F_DUPFD_CLOEXEC, 0);
    file_ = fd >= 0 ? ::fdopen(fd, "wb") : nullptr;
    if (!file_) {
        const int error = errno;
        if (fd >= 0)
            ::close(fd);
        throw Error(path + ": cannot write: " + std::strerror(error));
    }
    std::setvbuf(file_, nullptr, _IOFBF, 1 << 20);
    records_.resize(geometry_.patchCount());
    written_.assign(geometry_.patchCount(), false);

    // Placeholder header; the real one is written by finish() once offsets are known.
    const uint8_t zeros[kHeaderSize] = {};
    write(zeros, kHeaderSize);
}

ArchiveWriter::~ArchiveWriter()
{
    if (file_)
        std::fclose(file_);
}

void ArchiveWriter::write(const void* data, size_t size)
{
    if (size && std::fwrite(data, 1, size, file_) != size)
        throw Error(output_.finalPath() + ": write failed: " + std::strerror(errno));
    position_ += size;
}

void ArchiveWriter::writePatch(PatchRecord record, const std::vector<uint8_t>& block_errors,
                               const uint8_t* payload, size_t payload_size)
{
    writePatch(record, block_errors, allValidMask(), noSampleFlags(), payload, payload_size);
}

void ArchiveWriter::writePatch(PatchRecord record, const std::vector<uint8_t>& block_errors,
                               const std::vector<uint8_t>& validity,
                               const std::vector<uint8_t>& sample_flags, const uint8_t* payload,
                               size_t payload_size)
{
    if (validity.empty() || sample_flags.empty())
        throw Error(output_.finalPath() + ": internal error: empty validity mask or sample flags");
    const PatchId p{static_cast<int>(record.level), static_cast<int>(record.x),
                    static_cast<int>(record.y)};
    if (!geometry_.exists(p) || written_[geometry_.patchIndex(p)])
        throw Error(output_.finalPath() + ": internal error: patch written twice or out of range");
    record.offset = position_;
    record.block_errors_size = static_cast<uint32_t>(block_errors.size());
    record.size = static_cast<uint32_t>(block_errors.size() + validity.size() +
                                        sample_flags.size() + payload_size);
    record.crc32 = crc32(payload, payload_size,
                         crc32(sample_flags.data(), sample_flags.size(),
                               crc32(validity.data(), validity.size(),
                                     crc32(block_errors.data(), block_errors.size()))));
    write(block_errors.data(), block_errors.size());
    write(validity.data(), validity.size());
    write(sample_flags.data(), sample_flags.size());
    write(payload, payload_size);
    records_[geometry_.patchIndex(p)] = record;
    written_[geometry_.patchIndex(p)] = true;
    ++written_count_;
}

void ArchiveWriter::copyPatch(PatchRecord record, const uint8_t* blob)
{
    const PatchId p{static_cast<int>(record.level), static_cast<int>(record.x),
                    static_cast<int>(record.y)};
    if (!geometry_.exists(p) || written_[geometry_.patchIndex(p)])
        throw Error(output_.finalPath() + ": internal error: patch written twice or out of range");
    record.offset = position_;
    write(blob, record.size);
    records_[geometry_.patchIndex(p)] = record;
    written_[geometry_.patchIndex(p)] = true;
    ++written_count_;
}

void ArchiveWriter::finish(const std::string& metadata_json)
{
    if (written_count_ != geometry_.patchCount())
        throw Error(output_.finalPath() + ": internal error: " + std::to_string(written_count_) +
                    " of " + std::to_string(geometry_.patchCount()) + " patches written");
    // The metadata must satisfy what every reader checks (docs/FORMAT.md, "Metadata"): a
    // source whose geotransform no command could use is refused here, naming the key, rather
    // than written into an archive that every command then refuses.
    try {
        parseArchiveMetadata(metadata_json, header_);
    } catch (const Error& e) {
        throw Error(output_.finalPath() + ": cannot write: " + e.what());
    }
    header_.codec_tables_offset = position_;
    header_.codec_tables_size = static_cast<uint32_t>(codec_tables_.size());
    header_.codec_tables_crc32 = crc32(codec_tables_.data(), codec_tables_.size());
    write(codec_tables_.data(), codec_tables_.size());
    const std::vector<uint8_t> metadata = packMetadata(metadata_json, header_.version);
    header_.metadata_offset = position_;
    header_.metadata_size = static_cast<uint32_t>(metadata.size());
    header_.metadata_crc32 = crc32(metadata.data(), metadata.size());
    write(metadata.data(), metadata.size());
    const std::vector<uint8_t> index = packIndex(records_, header_.version);
    header_.index_offset = position_;
    header_.index_crc32 = crc32(index.data(), index.size());
    write(index.data(), index.size());

    uint8_t bytes[kHeaderSize];
    serializeHeader(header_, bytes);
    if (std::fseek(file_, 0, SEEK_SET) != 0 ||
        std::fwrite(bytes, 1, kHeaderSize, file_) != kHeaderSize)
        throw Error(output_.finalPath() + ": write failed: " + std::strerror(errno));
    const bool closed = std::fclose(file_) == 0;
    file_ = nullptr;
    if (!closed)
        throw Error(output_.finalPath() + ": write failed: " + std::strerror(errno));
    output_.commit();
}

} // namespace ridge::archive
