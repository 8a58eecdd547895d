#pragma once
// Synchronous patch loading for the renderers: reads and decodes patches of an archive and
// keeps the decoded ones in an LRU cache, so that a patch whose codec predicts from its
// parent (the progressive codec) finds its ancestors decoded already, and a patch that comes
// back into view is not decoded twice. The asynchronous streaming pipeline builds on this.
//
// Not thread-safe: one loader per render thread.
#include "ridge/archive/archive_reader.h"
#include "ridge/lod/chunk_mesh.h"
#include "ridge/stream/lru_cache.h"

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

namespace ridge::stream {

struct DecodedPatch {
    PatchId id;
    std::vector<uint16_t> codes;     // patch_size^2, row-major
    std::vector<float> block_errors; // λ(d), metres, TessellationBlockLayout order
    // The paper's CPU/GPU split (PatchStreamer with residuals_for_gpu): instead of codes, the
    // entropy-decoded residuals[patch_size^2] that the GPU turns into codes from the parent's
    // resident codes. block_errors is then empty when the archive derives λ (the GPU derives
    // it after reconstructing).
    // Stored in 16 bits a sample when every one fits (quantised prediction errors nearly
    // always do: it halves what a residual patch holds in the decoded cache), else in 32.
    std::vector<int16_t> residuals16;
    std::vector<int32_t> residuals;
    // Ulrich's chunk of the codes, built by the worker that decoded them
    // (StreamerOptions::chunk_tolerance), so that the render thread only uploads it.
    std::optional<lod::ChunkMesh> chunk;

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
               block_errors.size() * sizeof(float) + residuals.size() * sizeof(int32_t) +
               residuals16.size() * sizeof(int16_t) +
               (chunk ? chunk->indices.size() * sizeof(uint32_t) : 0);
    }
};

// Ulrich's chunk of patch `p` of `reader` from its decoded `codes`: simplified to
// chunk_tolerance·Err(P), within the patch's valid extent. The one formula the streamer's
// workers and the renderer's synchronous loads both build with.
lod::ChunkMesh patchChunk(const archive::ArchiveReader& reader, PatchId p, const uint16_t* codes,
                          double chunk_tolerance);

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
    PatchLoader(const archive::ArchiveReader& reader, size_t cache_patches = 512);

    // Decoded patch `p`, decoding its ancestors first when the codec needs them. Throws
    // ridge::Error naming the archive and the patch when a blob is corrupt.
    std::shared_ptr<const DecodedPatch> load(PatchId p);

    const LoaderStats& stats() const { return stats_; }
    const archive::ArchiveReader& reader() const { return reader_; }

  private:
    std::shared_ptr<const DecodedPatch> decode(PatchId p);

    const archive::ArchiveReader& reader_;
    LruCache<int64_t, std::shared_ptr<const DecodedPatch>> cache_; // by patch index
    LoaderStats stats_;
};

} // namespace ridge::stream
