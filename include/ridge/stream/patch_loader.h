#pragma once
// Synchronous patch loading for the renderers: reads and decodes patches of an archive and
// keeps the decoded ones in an LRU cache, so that a patch whose codec predicts from its
// parent (the progressive codec) finds its ancestors decoded already, and a patch that comes
// back into view is not decoded twice. The asynchronous streaming pipeline builds on this.
//
// Not thread-safe: one loader per render thread.
#include "ridge/archive/archive_reader.h"
#include "ridge/codec/progressive_reconstruction.h"
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
    // The paper's CPU/GPU split (PatchStreamer with residuals_for_gpu): instead of codes, the
    // entropy-decoded residuals[patch_size^2] that the GPU turns into codes from the parent's
    // resident codes. block_errors is then empty when the archive derives λ (the GPU derives
    // it after reconstructing).
    // Stored in 16 bits a sample when every one fits (quantised prediction errors nearly
    // always do: it halves what a residual patch holds in the decoded cache), else in 32.
    std::vector<int16_t> residuals16;
    std::vector<int32_t> residuals;
    // The samples the residuals cover (ProgressiveCodec::codedRegion); the rest repeats them.
    CodedRegion residual_region;
    // One product per preparation the loader or streamer was given, in their order, built by
    // the worker that decoded the codes so that the render thread only uploads them. Empty
    // for residual patches (no codes on the CPU).
    std::vector<std::shared_ptr<const PatchProduct>> prepared;

    // Sets drawable_cells from a decoded validity mask.
    void setDrawableCells(const PatchValidity& validity);

    bool needsGpuReconstruction() const
    {
        return codes.empty() && (!residuals.empty() || !residuals16.empty());
    }
    // Stores `values` as residuals16 when every one fits in 16 bits, else as residuals.
    void setResiduals(std::vector<int32_t> values);
    // The residuals in 32 bits, however they are stored.
    std::vector<int32_t> residualsWide() const;
    size_t bytes() const
    {
        return sizeof(*this) + codes.size() * sizeof(uint16_t) +
               block_errors.size() * sizeof(float) + drawable_cells.size() +
               sample_flags.flags.size() + residuals.size() * sizeof(int32_t) +
               residuals16.size() * sizeof(int16_t) + preparedBytes();
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
