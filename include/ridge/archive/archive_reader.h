#pragma once
// Random-access reader of a .ridge archive.
//
// Opening reads and checks only the header, the metadata and the index (48 bytes per
// patch); every patch is then read with one pread of its blob, so any patch can be fetched
// without touching the others. Every byte of the file is covered by a checksum (header,
// metadata, index, each blob) and all offsets and sizes are bounds-checked: archive bytes are
// untrusted.
//
// A checksum detects accidents, not a buggy writer or a hostile file, so opening also checks
// every field against docs/FORMAT.md where it is loaded: header numbers finite and in range
// (reserved bytes zero, codec parameters by the codec), the metadata parsed into
// ArchiveMetadata with its duplicates of the header cross-checked, each index entry's bounds
// finite, ordered and consistent with δ_l, parents' bounds covering their children, blobs
// tiling the patch area. What an open archive reports can be used without further checks
// (boxes, cameras and screen-space errors stay finite); what needs decoding (samples within
// min/max, λ) is checked by `ridge verify`.
//
// Errors are ridge::Error messages that start with the archive path and name the field or
// the patch they hit: "PATH: header field spacing_x is inf: must be a number in (0, 1e+07]",
// "PATH: index entry 3, patch (level 1, x 0, y 1): min_height 12 > max_height 3",
// "PATH: patch (level 3, x 5, y 2): checksum mismatch ...".
//
// Thread safety: after construction, every const member may be called concurrently.
#include "ridge/archive/archive_metadata.h"
#include "ridge/archive/format.h"
#include "ridge/codec/height_codec.h"
#include "ridge/core/height_grid.h"
#include "ridge/pyramid/level_pyramid.h"
#include "ridge/pyramid/sample_flags.h"
#include "ridge/pyramid/tessellation_block_errors.h"
#include "ridge/pyramid/validity_pyramid.h"

#include <memory>
#include <string>
#include <vector>

namespace ridge::archive {

// The largest codec tables region a reader loads (docs/FORMAT.md, "Codec tables"): progressive
// v2's tables at 32 levels take under 300 KB (2048 tables of at most 143 bytes, and weights),
// so a larger size is refused before anything is allocated.
inline constexpr uint32_t kMaxCodecTablesBytes = 1u << 20;

// The bytes of one blob by part (docs/FORMAT.md, "Patch blob"): what `ridge info --bytes`
// adds up.
struct BlobParts {
    size_t block_errors = 0;
    size_t validity = 0;     // the mask's kind byte and frame (version >= 2)
    size_t sample_flags = 0; // the flags' kind byte and frame (version >= 4)
    size_t payload = 0;
};

class ArchiveReader {
  public:
    explicit ArchiveReader(const std::string& path);
    ~ArchiveReader();
    ArchiveReader(const ArchiveReader&) = delete;
    ArchiveReader& operator=(const ArchiveReader&) = delete;

    const std::string& path() const { return path_; }
    const Header& header() const { return header_; }
    const PyramidGeometry& geometry() const { return geometry_; }
    // The metadata document as stored (valid JSON, checked), and its parsed fields.
    const std::string& metadataJson() const { return metadata_; }
    const ArchiveMetadata& metadata() const { return metadata_fields_; }
    const HeightCodec& codec() const { return *codec_; }
    PyramidFilter filter() const { return static_cast<PyramidFilter>(header_.filter_id); }
    TessellationBlockLayout blockLayout() const;
    HeightQuantization quantization() const;
    uint64_t fileSize() const { return file_size_; }

    // δ_l in metres: codec bound at `level` plus the quantization error of the source.
    double levelErrorBound(int level) const;

    const std::vector<PatchRecord>& index() const { return records_; }
    const PatchRecord& record(PatchId p) const { return records_[geometry_.patchIndex(p)]; }

    // Reads the blob of `p` and checks its checksum. Throws ridge::Error naming the patch.
    std::vector<uint8_t> readBlob(PatchId p) const;
    // Reads and decodes patch `p` into codes[patch_size^2]. `parent` is the parent's decoded
    // codes for codecs that predict from it (may be null for lossless codecs). When
    // `block_errors` is given it also receives λ(d) in metres, from the same read.
    void decodePatch(PatchId p, uint16_t* codes, const uint16_t* parent = nullptr,
                     std::vector<float>* block_errors = nullptr) const;
    // decodePatch from a blob readBlob(p) returned (a cached one, say); `parent` is required
    // when codec().needsParent(p.level).
    // `validity` and `sample_flags`, when given, receive the patch's validity mask and sample
    // flags from the same blob.
    void decodeBlob(PatchId p, const std::vector<uint8_t>& blob, uint16_t* codes,
                    const uint16_t* parent, std::vector<float>* block_errors = nullptr,
                    PatchValidity* validity = nullptr,
                    PatchSampleFlags* sample_flags = nullptr) const;

    // Which samples of `p` are data and which of its cells may be drawn
    // (pyramid/validity_pyramid.h): the mask stored after the block errors (version 2), or
    // all valid (version 1). Validated as it is read: kind, sizes, the zstd frame, padding
    // bits, canonical kind, drawable cells' corners; throws ridge::Error naming the patch and
    // the field.
    PatchValidity readValidity(PatchId p) const;
    PatchValidity validityOf(PatchId p, const std::vector<uint8_t>& blob) const;
    // Which samples of `p` are water and which were filled (pyramid/sample_flags.h): the
    // flags stored after the validity mask (version 4). Older archives have none stored:
    // no sample was filled that a reader can tell, and water is what the palette called it
    // then, a height <= 0 m, which only decoded heights can tell (storesSampleFlags()
    // false: renderers and queries apply that rule themselves). Validated as read: kind,
    // sizes, the zstd frame, padding bits, canonical kind, no flag on an invalid sample
    // (finest level, and every level with decimation).
    PatchSampleFlags readSampleFlags(PatchId p) const;
    PatchSampleFlags sampleFlagsOf(PatchId p, const std::vector<uint8_t>& blob) const;
    // Where the codec payload of `blob` starts (after block errors, validity mask and sample
    // flags); decodes the mask into `validity` and the flags into `sample_flags` when given.
    // Throws for a corrupt mask or flags.
    size_t payloadOffset(PatchId p, const std::vector<uint8_t>& blob,
                         PatchValidity* validity = nullptr,
                         PatchSampleFlags* sample_flags = nullptr,
                         BlobParts* parts = nullptr) const;
    // Whether the archive's blobs carry validity masks (format version >= 2).
    bool storesValidity() const { return header_.version >= kFirstVersionWithValidity; }
    // Whether they carry sample flags (format version >= 4).
    bool storesSampleFlags() const { return header_.version >= kFirstVersionWithSampleFlags; }

    // Decoding split between CPU and GPU (the codec's capabilities().gpu): true when
    // patches of `level` have a CPU half (decodeForGpu) that the codec's GPU decoder finishes.
    bool decodesOnGpu(int level) const;
    // The CPU half for such a patch, from its blob (HeightCodec::decodeForGpu). `block_errors`
    // receives the stored λ(d) in metres, or is cleared when the GPU must derive them: when the
    // archive does not store them, and for a refinable codec (a partial decode's λ is not the
    // stored one). `parent`: the parent's codes, required when the codec's CPU half reads
    // them (GpuDecoding::cpu_half_reads_parent) below the root. Throws ridge::Error naming the
    // patch for a corrupt blob.
    std::shared_ptr<const GpuPayload> decodeForGpu(PatchId p, const std::vector<uint8_t>& blob,
                                                   const uint16_t* parent,
                                                   std::vector<float>* block_errors) const;
    // The codes of `p` from what decodeForGpu gave for it, finished on the CPU
    // (HeightCodec::finishOnCpu, for codecs whose GpuDecoding::finishes_on_cpu): what
    // decodeBlob gives, without entropy-decoding the blob again. `parent`: the parent's codes.
    // Throws ridge::Error naming the patch when the codec cannot.
    void finishOnCpu(PatchId p, const GpuPayload& payload, const uint16_t* parent,
                     uint16_t* codes) const;
    // Reads λ(d) of every block of `p` in metres (see TessellationBlockLayout for the order).
    // Archives built without stored block errors derive them from the decoded heights
    // (exact for what is drawn; costs a decode).
    std::vector<float> readBlockErrors(PatchId p) const;
    // λ(d) in metres of decoded codes[patch_size^2], as a reader derives unstored ones.
    std::vector<float> deriveBlockErrors(const uint16_t* codes) const;

    // "PATH: patch (level L, x X, y Y)" for messages.
    std::string describe(PatchId p) const { return path_ + ": " + patchName(p); }
    // "patch (level L, x X, y Y)".
    static std::string patchName(PatchId p);

  private:
    // The steps of opening; each fails with a message naming the field.
    void loadHeader();
    std::vector<uint8_t> loadCodecTables();
    void checkGeometryFields();
    void loadMetadata();
    void loadIndex();
    void readAt(uint64_t offset, void* dst, size_t size, const std::string& what) const;
    std::vector<float> unpackBlockErrorsOf(PatchId p, const std::vector<uint8_t>& blob) const;

    [[noreturn]] void fail(const std::string& problem) const;

    // Owns the descriptor as a member so that it is closed when the constructor throws (a
    // destructor does not run for a half-constructed object).
    class FileDescriptor {
      public:
        explicit FileDescriptor(int fd = -1) : fd_(fd) {}
        ~FileDescriptor();
        FileDescriptor(const FileDescriptor&) = delete;
        FileDescriptor& operator=(const FileDescriptor&) = delete;
        int get() const { return fd_; }

      private:
        int fd_;
    };

    std::string path_;
    FileDescriptor fd_;
    uint64_t file_size_ = 0;
    Header header_;
    PyramidGeometry geometry_;
    std::string metadata_;
    ArchiveMetadata metadata_fields_;
    std::vector<PatchRecord> records_;
    std::unique_ptr<HeightCodec> codec_;
};

} // namespace ridge::archive
