#pragma once
// The texture arrays of resident patches (internal to ridge_render), as the paper's
// "Implementation Details" keeps them: height maps (R16UI codes), normal maps (RGBA8_SNORM,
// computed on the GPU when a patch becomes resident) and tessellation block errors (RGBA32F,
// λ^(1..4) per block), one layer per slot.
#include "ridge/core/height_grid.h"
#include "ridge/gpu/gl_objects.h"
#include "ridge/gpu/shader_program.h"
#include "ridge/pyramid/tessellation_block_errors.h"
#include "ridge/stream/patch_loader.h"

#include <vector>

namespace ridge::render {

class PatchTextures {
  public:
    // Needs a current GL 4.5 context. `levels` is D as the shaders use it (<= 4).
    PatchTextures(int patch_size, const TessellationBlockLayout& layout, int levels, int slots,
                  const HeightQuantization& quantization);

    // Uploads `patch` into `slot` and computes its normal map from `bordered` ((n+2)² heights
    // in code units, stream::borderedPatch). `cell_metres` is the patch's cell size along i
    // and j. `lambda_cap` bounds λ (the patch's height range): what lambdaMax reports.
    void upload(const stream::DecodedPatch& patch, int slot, const std::vector<float>& bordered,
                double cell_metres_i, double cell_metres_j, float lambda_cap);
    // Makes uploads visible to the draws that follow (one barrier per batch of uploads).
    void finishUploads() const;

    // Binds heights, normals and block errors to texture units 0, 1 and 2.
    void bind() const;
    // The largest λ^(d) of any block of the patch in `slot`, metres.
    float lambdaMax(int slot) const { return lambda_max_[size_t(slot)]; }

  private:
    int n_;
    TessellationBlockLayout layout_;
    int levels_;
    HeightQuantization quantization_;
    std::vector<float> lambda_max_;
    gpu::GlTexture heights_{GL_TEXTURE_2D_ARRAY};
    gpu::GlTexture normals_{GL_TEXTURE_2D_ARRAY};
    gpu::GlTexture block_errors_{GL_TEXTURE_2D_ARRAY};
    gpu::GlTexture bordered_{GL_TEXTURE_2D}; // staging for the normal-map pass
    gpu::ShaderProgram normal_program_;
};

} // namespace ridge::render
