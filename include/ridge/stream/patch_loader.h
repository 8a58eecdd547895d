#pragma once
// Synchronous patch loading for the renderers: reads and decodes patches of an archive and
// keeps the decoded ones in an LRU cache, so that a patch whose codec predicts from its
// parent (the progressive codec) finds its ancestors decoded already, and a patch that comes
// back into view is not decoded twice. The asynchronous streaming pipeline builds on this.
//
// Not thread-safe: one loader per render thread.
#include "ridge/archive/archive_reader.h"
#include "ridge/stream/lru_cache.h"

#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

namespace ridge::stream {

// What a LOD scheme derives from a patch's codes off the render thread (Ulrich's chunk mesh,
// geomorphing's vertex arrays): the stream carries it without knowing what it is.
struct PatchProduct {
    virtual ~PatchProduct() = default;
    virtual size_t bytes() const = 0; // RAM held, for the decoded-patch cache's budget
};
// Builds a scheme's product from patch `id`'s decoded codes (patch_size², row-major). Runs on
// the decode workers, concurrently: it must be thread-safe. Throws ridge::Error on failure
// (the patch then fails like a corrupt blob).
using PatchPreparation =
    std::function<std::shared_ptr<const PatchProduct>(PatchId id, const uint16_t* codes)>;

struct DecodedPatch {
    PatchId id;
    std::vector<uint16_t> codes;     // patch_size^2, row-major
    std::vector<float> block_errors; // λ(d), metres, TessellationBlockLayout order
    // Kept nodata: the patch's drawable cells ((n−1)², row-major, 1 = drawable; archive
    // validity mask); empty when every cell may be drawn (no cost for such patches).
    std::vector<uint8_t> drawable_cells;
    // Water and filled samples (archive sample flags, format version 4): kind None costs
    // nothing, AllWater nothing either, Mixed patch_size² bytes.
    PatchSampleFlags sample_flags;
    // Decoding split between CPU and GPU (PatchStreamer with gpu_decode): instead of codes,
    // the CPU half's output (ArchiveReader::decodeForGpu), which the codec's GPU decoder turns
    // into codes. block_errors is then empty when the GPU derives λ after decoding.
    std::shared_ptr<const GpuPayload> gpu_payload;
    // One product per preparation the loader or streamer was given, in their order, built by
    // the worker that decoded the codes so that the render thread only uploads them. Empty
    // for patches decoded on the GPU (no codes on the CPU).
    std::vector<std::shared_ptr<const PatchProduct>> prepared;

    // Sets drawable_cells from a decoded validity mask.
    void setDrawableCells(const PatchValidity& validity);

    bool decodesOnGpu() const { return codes.empty() && gpu_payload != nullptr; }
    size_t bytes() const
    {
        return sizeof(*this) + codes.size() * sizeof(uint16_t) +
               block_errors.size() * sizeof(float) + drawable_cells.size() +
               sample_flags.flags.size() + (gpu_payload ? gpu_payload->bytes() : 0) +
               preparedBytes();
    }
    size_t preparedBytes() const
    {
        size_t total = 0;
        for (const auto& product : prepared)
            total += product ? product->bytes() : 0;
        return total;
    }
};

// Runs `preparations` on `patch`'s codes into patch.prepared (the loader's and the streamer's
// workers' one way of doing it).
void prepareProducts(DecodedPatch& patch, const std::vector<PatchPreparation>& preparations);

struct LoaderStats {
    uint64_t decoded = 0; // patches decoded (ancestors included)
    uint64_t cache_hits = 0;
    uint64_t bytes_read = 0;    // blob bytes
    uint64_t bytes_decoded = 0; // DecodedPatch::bytes() of what was decoded
};

class PatchLoader {
  public:
    // Keeps at most `cache_patches` decoded patches (>= the pyramid depth, so that an ancestor
    // chain always fits).
    // `preparations` run on every patch it decodes (DecodedPatch::prepared).
    PatchLoader(const archive::ArchiveReader& reader, size_t cache_patches = 512,
                std::vector<PatchPreparation> preparations = {});

    // Decoded patch `p`, decoding its ancestors first when the codec needs them. Throws
    // ridge::Error naming the archive and the patch when a blob is corrupt.
    std::shared_ptr<const DecodedPatch> load(PatchId p);

    const LoaderStats& stats() const { return stats_; }
    const archive::ArchiveReader& reader() const { return reader_; }

  private:
    std::shared_ptr<const DecodedPatch> decode(PatchId p);

    const archive::ArchiveReader& reader_;
    std::vector<PatchPreparation> preparations_;
    LruCache<int64_t, std::shared_ptr<const DecodedPatch>> cache_; // by patch index
    LoaderStats stats_;
};

} // namespace ridge::stream
