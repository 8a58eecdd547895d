#pragma once
// The GPU half of the fractal codec (internal to ridge_render): the iterations of the
// fractal-rings paper's decoder (§7) as compute passes (shaders/fractal_iterate.comp) over
// the transforms the CPU parsed (FractalCodec::decodeForGpu). Each slot keeps its iterate, so
// a patch decoded with few iterations (Base incremental: far away) is refined in place by
// applying more (refine) without reading or uploading anything again. Bit-identical to
// FractalCodec::decodePartial at every iteration count (tests/render/decoders/
// gpu_fractal_decoder_test.cpp). Needs a current GL 4.5 context.
#include "gpu_patch_decoder.h"

#include "ridge/codec/fractal_codec.h"
#include "ridge/gpu/gl_objects.h"
#include "ridge/gpu/shader_program.h"

#include <vector>

namespace ridge::render {

class GpuFractalDecoder final : public GpuPatchDecoder {
  public:
    // Room for `slots` patches of `patch_size` samples a side.
    GpuFractalDecoder(int patch_size, int slots);

    // GPU memory per slot: the iterate, the transforms and the samples (bytes).
    static double bytesPerSlot(int patch_size);

    // Uploads the payload into target.layer's state and applies min(steps, N) iterations.
    void decode(const GpuPayload& payload, const Target& target, int steps) override;
    void refine(const Target& target, int steps) override;
    // Iterations applied to the patch in `slot` (0 before any decode).
    int steps(int slot) const { return steps_[size_t(slot)]; }

  private:
    void iterate(const Target& target, int from, int to);

    int n_, m_, ranges_;
    gpu::GlBuffer state_, transforms_, samples_, scratch_;
    gpu::ShaderProgram program_;
    std::vector<int> steps_, full_steps_, step_unit_, pinned_;
};

} // namespace ridge::render
