#pragma once
// The texture arrays of resident patches (internal to ridge_render), as the paper's
// "Implementation Details" keeps them: height maps (R16UI codes), normal maps (RGBA8_SNORM,
// computed on the GPU when a patch becomes resident) and tessellation block errors (RGBA32F,
// λ^(1..4) per block), one layer per slot.
//
// A patch arrives either as codes decoded on the CPU (upload) or as its codec's CPU half,
// which the codec's GPU decoder finishes (decodeOnGpu; decoders/gpu_patch_decoder.h), maybe
// from its parent's layer, maybe partially and refined in place later (refine); λ is then
// derived on the GPU too unless the archive stores it. Normal maps are computed from the
// height layers once a batch is written (computeNormals).
#include "ridge/archive/archive_reader.h"
#include "ridge/core/height_grid.h"
#include "ridge/gpu/gl_objects.h"
#include "ridge/gpu/shader_program.h"
#include "ridge/lod/projected_grid.h"
#include "ridge/pyramid/tessellation_block_errors.h"
#include "ridge/stream/patch_loader.h"

#include "decoders/gpu_patch_decoder.h"

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace ridge::render {

class PatchTextures {
  public:
    // Whether slots hold water maps for `reader`'s patches: only when they may carry water
    // bitmaps (archive sample flags with any water sample).
    static bool waterMaps(const archive::ArchiveReader& reader);
    // Texture memory one slot takes, bytes (what the constructor allocates per slot).
    // `gpu_codec`: the codec whose GPU decoder the slots serve (its per-slot state), or null.
    static double bytesPerSlot(int patch_size, const TessellationBlockLayout& layout,
                               bool water_maps, const HeightCodec* gpu_codec = nullptr);
    // Slots for resident patches of `reader`: at most `max_slots`, at most what
    // `vram_budget_mb` holds at bytesPerSlot plus `scheme_slot_bytes` (what the schemes keep
    // per slot), after `scheme_fixed_bytes` (what they hold beside the slots), and at most the
    // GL limit on array layers. At least 4, so that raising ε always finds a selection that
    // fits: throws ridge::Error naming the archive otherwise.
    static int slotCount(const archive::ArchiveReader& reader, double scheme_slot_bytes,
                         double vram_budget_mb, int max_slots,
                         const HeightCodec* gpu_codec = nullptr, double scheme_fixed_bytes = 0.0);

    // Needs a current GL 4.5 context. `levels` is D as the shaders use it (<= 4).
    // `gpu_codec`: the archive's codec when patches may arrive as its CPU half (decodeForGpu),
    // else null; it must have a registered GPU decoder.
    // `water_maps`: patches may carry water bitmaps (archive sample flags), which then take
    // n² bytes per slot; else a single layer is allocated and never written.
    PatchTextures(int patch_size, const TessellationBlockLayout& layout, int levels, int slots,
                  const HeightQuantization& quantization, const HeightCodec* gpu_codec = nullptr,
                  bool water_maps = false);
    ~PatchTextures();
    PatchTextures(const PatchTextures&) = delete;
    PatchTextures& operator=(const PatchTextures&) = delete;

    // Uploads `patch` (codes and λ) into `slot`. `lambda_cap` bounds λ (the patch's height
    // range): what lambdaMax reports.
    void upload(const stream::DecodedPatch& patch, int slot, float lambda_cap);
    // Decodes `patch` (decodesOnGpu) into `slot` with the codec's GPU decoder, from the codes
    // in `parent_slot` when the codec reads its parent (−1 otherwise), applying `steps` of a
    // refinable codec's steps, and derives λ unless the patch carries it. Until a derived λ's
    // readback arrives (collect), lambdaMax reports `lambda_cap`.
    void decodeOnGpu(const stream::DecodedPatch& patch, int parent_slot, int slot, int steps,
                     float lambda_cap);
    // Refines the patch `p` in `slot` (decoded by a refinable codec) to `steps` and derives its
    // λ again; its normal map follows in computeNormals.
    void refine(PatchId p, int slot, int steps, float lambda_cap);
    // The normal map of the patch in `slot` from the height layers: its own and, for the ring
    // one sample beyond its border, its same-level neighbours' in `neighbour_slots` (west,
    // east, north, south; −1 extrapolates). `cell_metres` is the cell size along i and j; on
    // a globe (`latitude_step` ≠ 0) the one along i is taken at the equator and shrinks with
    // the cosine of the latitude of each row, row j at latitude0 + j·latitude_step (radians).
    // The heights it reads must be written (uploads of the batch done).
    void computeNormals(int slot, const std::array<int, 4>& neighbour_slots, double cell_metres_i,
                        double cell_metres_j, double latitude0 = 0.0, double latitude_step = 0.0);
    // A projected grid on the globe: its lattice (absoluteLatticeTexture), whose tangents
    // computeNormalsOnGrid turns normals by. `grid` must outlive this.
    void setGridAxes(const lod::ProjectedGrid& grid);
    // The normal map of the patch in `slot` on a projected grid (setGridAxes first), in east,
    // north, up: finest sample (column0, row0) is its sample (0, 0), `step` finest samples
    // per cell. Neighbours as computeNormals.
    void computeNormalsOnGrid(int slot, const std::array<int, 4>& neighbour_slots, int64_t column0,
                              int64_t row0, int64_t step);
    // What upload() or decodeOnGpu() sends for `patch`, bytes: the per-frame budget plans
    // with it and FrameStats counts it.
    size_t uploadBytes(const stream::DecodedPatch& patch) const;
    // Makes uploads visible to the draws that follow (one barrier per batch of uploads) and
    // fences the λ maxima derived in the batch for collect().
    void finishUploads();
    // Takes the λ maxima whose fence has passed (never waits).
    void collect();

    // Binds heights, normals and block errors to texture units 0, 1 and 2, the cell masks
    // and their per-slot flags to 4 and 5, the water maps to 6 (terrain.frag; 3 is
    // geomorph's).
    void bind() const;
    // Read back from the GPU (tests): the codes of `slot` (n², row-major), its λ(d) in metres
    // (B² blocks of D = the layout's levels, TessellationBlockLayout order; levels beyond 4 read
    // 0) and its normal map (RGBA8_SNORM texels, row-major).
    std::vector<uint16_t> readCodes(int slot) const;
    std::vector<float> readBlockErrors(int slot) const;
    std::vector<int8_t> readNormals(int slot) const;
    // The largest λ^(d) of any block of the patch in `slot`, metres.
    float lambdaMax(int slot) const { return lambda_max_[size_t(slot)]; }

  private:
    void uploadBlockErrors(const stream::DecodedPatch& patch, int slot, float lambda_cap);
    // The patch's drawable cells and water bitmap into their layers, and the slot's flags
    // (1: cell mask, 2: water bitmap, 4: all water; terrain.frag): a patch without nodata or
    // water sends nothing but a one-byte flag reset when its slot held such a patch.
    void uploadMasks(const stream::DecodedPatch& patch, int slot);
    // λ of the codes in `slot` on the GPU (block_errors.comp), read back at collect().
    void deriveBlockErrors(int slot, float lambda_cap);
    // Binds the normal program's inputs common to every frame and dispatches it for `slot`
    // (its own uniforms set).
    void dispatchNormals(int slot, const std::array<int, 4>& neighbours);

    int n_;
    TessellationBlockLayout layout_;
    int levels_;
    HeightQuantization quantization_;
    std::vector<float> lambda_max_;
    std::vector<float> lambda_cap_;
    std::vector<uint32_t> generation_; // per slot: bumps on every upload
    std::vector<uint8_t> masked_;      // per slot: its mask_flags_ byte
    gpu::GlTexture heights_{GL_TEXTURE_2D_ARRAY};
    gpu::GlTexture normals_{GL_TEXTURE_2D_ARRAY};
    gpu::GlTexture block_errors_{GL_TEXTURE_2D_ARRAY};
    gpu::GlTexture cell_masks_{GL_TEXTURE_2D_ARRAY}; // R8UI, C x C per slot
    gpu::GlTexture mask_flags_{GL_TEXTURE_1D};       // R8UI, one texel per slot
    gpu::GlTexture water_maps_{GL_TEXTURE_2D_ARRAY}; // R8UI sample flags, n x n per slot
    bool water_maps_allocated_ = false;
    gpu::GlBuffer lambda_max_bits_; // per slot, written by block_errors.comp
    gpu::ShaderProgram normal_program_;
    const lod::ProjectedGrid* grid_ = nullptr; // setGridAxes
    std::optional<gpu::GlTexture> lattice_;    // absoluteLatticeTexture
    gpu::ShaderProgram block_error_program_;
    std::unique_ptr<GpuPatchDecoder> decoder_;
    // λ maxima derived on the GPU, waiting for their fence.
    struct PendingSlot {
        int slot;
        uint32_t generation;
    };
    std::vector<PendingSlot> derived_in_batch_;
    // A copy of the maxima per batch, so that reading it after its fence never waits for
    // batches submitted later (they write lambda_max_bits_, not the copy).
    struct PendingReadback {
        GLsync fence;
        gpu::GlBuffer copy;
        std::vector<PendingSlot> slots;
    };
    std::vector<PendingReadback> pending_;
};

} // namespace ridge::render
