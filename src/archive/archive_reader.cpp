#include "ridge/archive/archive_reader.h"

#include "index_checks.h"
#include "ridge/archive/block_error_storage.h"
#include "ridge/archive/sample_flags_storage.h"
#include "ridge/archive/validity_storage.h"
#include "ridge/codec/progressive_codec.h"
#include "ridge/core/crc32.h"
#include "ridge/core/error.h"
#include "ridge/pyramid/patch_context.h"

#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <limits>
#include <sys/stat.h>
#include <unistd.h>

namespace ridge::archive {

namespace {

std::string hex32(uint32_t v)
{
    char buf[16];
    std::snprintf(buf, sizeof(buf), "0x%08x", v);
    return buf;
}

} // namespace

ArchiveReader::FileDescriptor::~FileDescriptor()
{
    if (fd_ >= 0)
        ::close(fd_);
}

ArchiveReader::ArchiveReader(const std::string& path)
    : path_(path), fd_(::open(path.c_str(), O_RDONLY | O_CLOEXEC))
{
    if (fd_.get() < 0)
        fail(std::strerror(errno));
    struct stat st;
    if (::fstat(fd_.get(), &st) != 0 || !S_ISREG(st.st_mode))
        fail("not a regular file");
    file_size_ = static_cast<uint64_t>(st.st_size);
    if (file_size_ < kHeaderSize)
        fail("not a ridge archive (file too short: " + std::to_string(file_size_) + " bytes)");
    loadHeader();
    loadMetadata();
    loadIndex();
}

void ArchiveReader::loadHeader()
{
    // Magic, version, checksum and the numbers (parseHeader), then what needs the geometry
    // and the codecs.
    uint8_t bytes[kHeaderSize];
    readAt(0, bytes, kHeaderSize, "header");
    if (std::string problem = parseHeader(bytes, header_); !problem.empty())
        fail(problem);
    checkGeometryFields();
    if (header_.filter_id > static_cast<uint32_t>(PyramidFilter::Neville4))
        fail("header field filter_id is " + std::to_string(header_.filter_id) +
             ": must be 0 (decimation) or 1 (Neville-4)");
    CodecSettings settings;
    settings.level_count = static_cast<int>(header_.level_count);
    settings.param[0] = header_.codec_param[0];
    settings.param[1] = header_.codec_param[1];
    settings.tables = loadCodecTables();
    std::string problem;
    codec_ = makeCodec(static_cast<CodecId>(header_.codec_id), settings, &problem);
    if (!codec_)
        fail("header field " + problem);
    // Tables only where the codec has them: a codec without per-archive tables stores none,
    // whatever it does with the region (raw and lossless ignore it; bytes nobody reads would
    // be a checksummed hiding place).
    if (!settings.tables.empty() && codec_->storeTables().empty())
        fail("codec tables region of " + std::to_string(settings.tables.size()) + " bytes: the " +
             codec_->name() +
             " codec has no codec tables (only progressive v2 stores any): must be empty");
}

std::vector<uint8_t> ArchiveReader::loadCodecTables()
{
    // Version 3: between the blobs and the metadata, its own checksummed region.
    if (header_.version < kFirstVersionWithCodecTables)
        return {};
    const Header& h = header_;
    if (h.codec_tables_offset < kHeaderSize || h.codec_tables_offset > file_size_ ||
        h.codec_tables_size > file_size_ - h.codec_tables_offset)
        fail("header fields codec_tables_offset " + std::to_string(h.codec_tables_offset) +
             " and codec_tables_size " + std::to_string(h.codec_tables_size) +
             " lie outside the file (truncated?)");
    if (h.codec_tables_size > kMaxCodecTablesBytes)
        fail("header field codec_tables_size is " + std::to_string(h.codec_tables_size) +
             ": must be at most " + std::to_string(kMaxCodecTablesBytes) +
             " (the largest tables a codec stores)");
    if (h.codec_tables_offset + h.codec_tables_size != h.metadata_offset)
        fail("header fields codec_tables_offset + codec_tables_size (" +
             std::to_string(h.codec_tables_offset + h.codec_tables_size) +
             ") must equal metadata_offset (" + std::to_string(h.metadata_offset) +
             "): the metadata follows the codec tables");
    std::vector<uint8_t> tables(h.codec_tables_size);
    readAt(h.codec_tables_offset, tables.data(), tables.size(), "codec tables");
    if (crc32(tables.data(), tables.size()) != h.codec_tables_crc32)
        fail("codec tables checksum mismatch (stored " + hex32(h.codec_tables_crc32) +
             ", computed " + hex32(crc32(tables.data(), tables.size())) + ")");
    return tables;
}

void ArchiveReader::checkGeometryFields()
{
    // PyramidGeometry takes int extents; every valid one fits.
    constexpr uint32_t kMaxExtent = std::numeric_limits<int>::max();
    for (const auto& [field, value] :
         {std::pair{"width", header_.width}, std::pair{"height", header_.height}})
        if (value < 2 || value > kMaxExtent)
            fail(std::string("header field ") + field + " is " + std::to_string(value) +
                 ": must be an integer in [2, " + std::to_string(kMaxExtent) + "]");
    const uint32_t n = header_.patch_size;
    if (n < 5 || n > 4097 || ((n - 1) & (n - 2)) != 0)
        fail("header field patch_size is " + std::to_string(n) +
             ": must be 2^k + 1 with k in [2, 12] (5, 9, 17, ..., 4097)");
    try {
        geometry_ = PyramidGeometry(static_cast<int>(header_.width),
                                    static_cast<int>(header_.height), static_cast<int>(n));
    } catch (const Error& e) {
        fail(std::string("invalid geometry in header: ") + e.what());
    }
    if (static_cast<uint32_t>(geometry_.levelCount()) != header_.level_count)
        fail("header field level_count is " + std::to_string(header_.level_count) + ": must be " +
             std::to_string(geometry_.levelCount()) + " for a " + std::to_string(header_.width) +
             " x " + std::to_string(header_.height) + " grid of " + std::to_string(n) +
             "-sample patches");
    const TessellationBlockLayout layout = blockLayout();
    if (header_.block_cells > n || !layout.valid())
        fail("header field block_cells is " + std::to_string(header_.block_cells) +
             ": must be a power of two >= 2 dividing patch_size - 1 = " + std::to_string(n - 1));
    if (static_cast<uint32_t>(layout.levels()) != header_.block_levels)
        fail("header field block_levels is " + std::to_string(header_.block_levels) +
             ": must be min(4, log2 block_cells) = " + std::to_string(layout.levels()));
}

void ArchiveReader::loadMetadata()
{
    // Between the blobs and the index, which ends the file: every byte is in one region.
    if (header_.metadata_offset < kHeaderSize || header_.metadata_offset > file_size_ ||
        header_.metadata_size > file_size_ - header_.metadata_offset ||
        header_.metadata_offset + header_.metadata_size > header_.index_offset)
        fail("metadata lies outside the file (truncated?)");
    if (header_.metadata_offset + header_.metadata_size != header_.index_offset)
        fail("header fields metadata_offset + metadata_size (" +
             std::to_string(header_.metadata_offset + header_.metadata_size) +
             ") must equal index_offset (" + std::to_string(header_.index_offset) +
             "): the index follows the metadata");
    if (header_.metadata_size > kMaxMetadataBytes)
        fail("header field metadata_size is " + std::to_string(header_.metadata_size) +
             ": must be at most " + std::to_string(kMaxMetadataBytes));
    std::vector<uint8_t> region(header_.metadata_size);
    readAt(header_.metadata_offset, region.data(), region.size(), "metadata");
    if (crc32(region.data(), region.size()) != header_.metadata_crc32)
        fail("metadata checksum mismatch (corrupt metadata)");
    if (const std::string why =
            unpackMetadata(region.data(), region.size(), header_.version, metadata_);
        !why.empty())
        fail(why);
    try {
        metadata_fields_ = parseArchiveMetadata(metadata_, header_);
    } catch (const Error& e) {
        fail(e.what());
    }
}

void ArchiveReader::loadIndex()
{
    // The last bytes of the file, one entry per patch of the geometry. The count comes from
    // untrusted fields: compare it with the file before multiplying (count · 48 may overflow).
    const uint64_t count = static_cast<uint64_t>(geometry_.patchCount());
    const uint64_t room = file_size_ - std::min(header_.index_offset, file_size_);
    const bool packed = header_.version >= kFirstVersionWithPackedIndex;
    if (header_.index_offset > file_size_ || (!packed && count > room / kIndexEntrySize))
        fail("index lies outside the file (truncated archive): " + std::to_string(count) +
             " patches need " + std::to_string(count) + " x " + std::to_string(kIndexEntrySize) +
             " bytes, " + std::to_string(room) + " remain");
    if (!packed && room != count * kIndexEntrySize)
        fail("unexpected bytes after the index");
    // A packed index may expand a lot (zstd), so its count is bounded by the blobs instead:
    // every blob holds at least a validity kind, a sample-flags kind and one payload byte.
    const uint64_t blob_area =
        header_.patchAreaEnd() - std::min<uint64_t>(header_.patchAreaEnd(), kHeaderSize);
    if (packed && count > blob_area / 3)
        fail("index lies outside the file (truncated archive): " + std::to_string(count) +
             " patches need at least 3 blob bytes each, the blobs have " +
             std::to_string(blob_area));
    std::vector<uint8_t> stored(room);
    readAt(header_.index_offset, stored.data(), stored.size(), "index");
    if (crc32(stored.data(), stored.size()) != header_.index_crc32)
        fail("index checksum mismatch (corrupt index)");
    std::vector<uint8_t> index;
    if (std::string problem =
            unpackIndex(stored.data(), stored.size(), count, header_.version, index);
        !problem.empty())
        fail(problem);

    IndexContext ctx{header_, geometry_, {}};
    for (int l = 0; l < geometry_.levelCount(); ++l)
        ctx.level_bound.push_back(levelErrorBound(l));
    records_.resize(count);
    for (uint64_t i = 0; i < count; ++i) {
        records_[i] = parseRecord(index.data() + i * kIndexEntrySize);
        if (std::string problem = checkIndexEntry(ctx, static_cast<int64_t>(i), records_[i]);
            !problem.empty())
            fail(problem);
    }
    if (std::string problem = checkIndexHierarchy(ctx, records_); !problem.empty())
        fail(problem);
    if (std::string problem = checkBlobTiling(ctx, records_); !problem.empty())
        fail(problem);
}

ArchiveReader::~ArchiveReader() = default;

TessellationBlockLayout ArchiveReader::blockLayout() const
{
    return {static_cast<int>(header_.patch_size), static_cast<int>(header_.block_cells)};
}

HeightQuantization ArchiveReader::quantization() const
{
    return {header_.height_scale, header_.height_offset, header_.quantization_error};
}

double ArchiveReader::levelErrorBound(int level) const
{
    return codec_->levelErrorBound(level) * header_.height_scale + header_.quantization_error;
}

std::string ArchiveReader::patchName(PatchId p)
{
    return "patch (level " + std::to_string(p.level) + ", x " + std::to_string(p.x) + ", y " +
           std::to_string(p.y) + ")";
}

void ArchiveReader::fail(const std::string& problem) const
{
    throw Error(path_ + ": " + problem);
}

void ArchiveReader::readAt(uint64_t offset, void* dst, size_t size, const std::string& what) const
{
    auto* p = static_cast<uint8_t*>(dst);
    while (size > 0) {
        const ssize_t n = ::pread(fd_.get(), p, size, static_cast<off_t>(offset));
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0)
            fail("cannot read " + what +
                 (n < 0 ? std::string(": ") + std::strerror(errno)
                        : std::string(": unexpected end of file")));
        p += n;
        offset += static_cast<uint64_t>(n);
        size -= static_cast<size_t>(n);
    }
}

std::vector<uint8_t> ArchiveReader::readBlob(PatchId p) const
{
    if (!geometry_.exists(p))
        throw Error(describe(p) + ": no such patch");
    const PatchRecord& r = record(p);
    std::vector<uint8_t> blob(r.size);
    readAt(r.offset, blob.data(), blob.size(), patchName(p));
    const uint32_t actual = crc32(blob.data(), blob.size());
    if (actual != r.crc32)
        throw Error(describe(p) + ": checksum mismatch (stored " + hex32(r.crc32) + ", computed " +
                    hex32(actual) + "): corrupt patch data");
    return blob;
}

void ArchiveReader::decodePatch(PatchId p, uint16_t* codes, const uint16_t* parent,
                                std::vector<float>* block_errors) const
{
    std::vector<uint16_t> ancestor;
    if (!parent && codec_->needsParent(p.level)) {
        // Random access to a progressive patch: decode its ancestors first (O(level) patches;
        // level-wide decoders pass the parent instead).
        ancestor.resize(static_cast<size_t>(geometry_.patchSize()) * geometry_.patchSize());
        decodePatch(p.parent(), ancestor.data());
        parent = ancestor.data();
    }
    decodeBlob(p, readBlob(p), codes, parent, block_errors);
}

size_t ArchiveReader::payloadOffset(PatchId p, const std::vector<uint8_t>& blob,
                                    PatchValidity* validity, PatchSampleFlags* sample_flags,
                                    BlobParts* parts) const
{
    const PatchRecord& r = record(p);
    const int n = geometry_.patchSize();
    if (blob.size() < r.block_errors_size)
        fail(patchName(p) + ": blob shorter than its block errors");
    BlobParts local_parts;
    BlobParts& part = parts ? *parts : local_parts;
    part = {r.block_errors_size, 0, 0, blob.size() - r.block_errors_size};
    if (sample_flags)
        *sample_flags = PatchSampleFlags{PatchSampleFlags::Kind::None, n, {}};
    if (!storesValidity()) {
        if (validity)
            *validity = PatchValidity{PatchValidity::Kind::AllValid, n, {}, {}};
        return r.block_errors_size;
    }
    PatchValidity local_validity;
    PatchValidity& v = validity ? *validity : local_validity;
    size_t offset = r.block_errors_size, consumed = 0;
    // The rules that tie a mask's bits to its samples hold at the finest level of either
    // filter and at every level of decimation (Neville's coarse validity is conservative).
    const bool corners_rule =
        filter() == PyramidFilter::Decimate || p.level == geometry_.finestLevel();
    std::string problem =
        unpackValidity(blob.data() + offset, blob.size() - offset, n, corners_rule, v, consumed);
    if (!problem.empty())
        throw Error(describe(p) + ": " + problem);
    offset += consumed;
    part.validity = consumed;
    if (storesSampleFlags()) {
        PatchSampleFlags local_flags;
        problem = unpackSampleFlags(
            blob.data() + offset, blob.size() - offset, n, corners_rule ? &v : nullptr,
            sample_flags ? *sample_flags : local_flags, consumed, header_.version);
        if (!problem.empty())
            throw Error(describe(p) + ": " + problem);
        offset += consumed;
        part.sample_flags = consumed;
    }
    if (offset >= blob.size())
        throw Error(describe(p) + ": masks of " + std::to_string(offset - r.block_errors_size) +
                    " bytes leave no payload in a blob of " + std::to_string(blob.size()) +
                    " bytes");
    part.payload = blob.size() - offset;
    return offset;
}

PatchSampleFlags ArchiveReader::sampleFlagsOf(PatchId p, const std::vector<uint8_t>& blob) const
{
    PatchSampleFlags f;
    payloadOffset(p, blob, nullptr, &f);
    return f;
}

PatchSampleFlags ArchiveReader::readSampleFlags(PatchId p) const
{
    if (!geometry_.exists(p))
        throw Error(describe(p) + ": no such patch");
    if (!storesSampleFlags())
        return PatchSampleFlags{PatchSampleFlags::Kind::None, geometry_.patchSize(), {}};
    return sampleFlagsOf(p, readBlob(p));
}

PatchValidity ArchiveReader::validityOf(PatchId p, const std::vector<uint8_t>& blob) const
{
    PatchValidity v;
    payloadOffset(p, blob, &v);
    return v;
}

PatchValidity ArchiveReader::readValidity(PatchId p) const
{
    if (!storesValidity()) {
        if (!geometry_.exists(p))
            throw Error(describe(p) + ": no such patch");
        return PatchValidity{PatchValidity::Kind::AllValid, geometry_.patchSize(), {}, {}};
    }
    return validityOf(p, readBlob(p));
}

void ArchiveReader::decodeBlob(PatchId p, const std::vector<uint8_t>& blob, uint16_t* codes,
                               const uint16_t* parent, std::vector<float>* block_errors,
                               PatchValidity* validity, PatchSampleFlags* sample_flags) const
{
    const PatchRecord& r = record(p);
    const size_t payload = payloadOffset(p, blob, validity, sample_flags);
    if (block_errors && r.block_errors_size > 0)
        *block_errors = unpackBlockErrorsOf(p, blob);
    const PatchContext ctx = patchContext(geometry_, p, parent);
    const int status = codec_->decode(codes, blob.data() + payload, blob.size() - payload, ctx);
    if (status != kCodecOk)
        throw Error(describe(p) + ": cannot decode: " + codecStatusMessage(status));
    if (block_errors && r.block_errors_size == 0)
        *block_errors = deriveBlockErrors(codes);
}

bool ArchiveReader::decodesOnGpu(int level) const
{
    return codec_->capabilities().gpu.decodes(level);
}

std::shared_ptr<const GpuPayload>
ArchiveReader::decodeForGpu(PatchId p, const std::vector<uint8_t>& blob, const uint16_t* parent,
                            std::vector<float>* block_errors) const
{
    const GpuDecoding gpu = codec_->capabilities().gpu;
    if (!gpu.decodes(p.level))
        throw Error(describe(p) + ": internal error: the codec does not decode it on the GPU");
    const PatchRecord& r = record(p);
    const size_t payload = payloadOffset(p, blob, nullptr);
    if (block_errors) {
        block_errors->clear();
        if (r.block_errors_size > 0 && !gpu.refinable)
            *block_errors = unpackBlockErrorsOf(p, blob);
    }
    if (gpu.cpu_half_reads_parent && p.level > 0 && !parent)
        throw Error(describe(p) + ": internal error: no parent to decode from");
    const PatchContext ctx = patchContext(geometry_, p, parent);
    std::shared_ptr<const GpuPayload> out;
    const int status =
        codec_->decodeForGpu(blob.data() + payload, blob.size() - payload, ctx, &out);
    if (status != kCodecOk || !out)
        throw Error(describe(p) + ": cannot decode: " +
                    codecStatusMessage(status != kCodecOk ? status : kCodecCorrupt));
    return out;
}

void ArchiveReader::finishOnCpu(PatchId p, const GpuPayload& payload, const uint16_t* parent,
                                uint16_t* codes) const
{
    if (!codec_->capabilities().gpu.finishes_on_cpu || !decodesOnGpu(p.level))
        throw Error(describe(p) + ": internal error: the codec cannot finish it on the CPU");
    const int status = codec_->finishOnCpu(payload, patchContext(geometry_, p, parent), codes);
    if (status != kCodecOk)
        throw Error(describe(p) +
                    ": cannot finish its GPU payload on the CPU: " + codecStatusMessage(status));
}

std::vector<float> ArchiveReader::deriveBlockErrors(const uint16_t* codes) const
{
    const TessellationBlockLayout layout = blockLayout();
    std::vector<float> lambda(static_cast<size_t>(layout.valuesPerPatch()));
    computeTessellationBlockErrors(codes, layout, lambda.data());
    for (float& v : lambda)
        v = static_cast<float>(v * header_.height_scale);
    return lambda;
}

std::vector<float> ArchiveReader::readBlockErrors(PatchId p) const
{
    if (record(p).block_errors_size == 0) {
        std::vector<float> lambda;
        std::vector<uint16_t> codes(static_cast<size_t>(geometry_.patchSize()) *
                                    geometry_.patchSize());
        decodePatch(p, codes.data(), nullptr, &lambda);
        return lambda;
    }
    return unpackBlockErrorsOf(p, readBlob(p));
}

std::vector<float> ArchiveReader::unpackBlockErrorsOf(PatchId p,
                                                      const std::vector<uint8_t>& blob) const
{
    const size_t count = static_cast<size_t>(blockLayout().valuesPerPatch());
    std::vector<float> lambda(count);
    if (!unpackBlockErrors(blob.data(), record(p).block_errors_size, count, lambda.data()))
        throw Error(describe(p) + ": corrupt tessellation block errors");
    return lambda;
}

} // namespace ridge::archive
