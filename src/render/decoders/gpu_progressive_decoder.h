#pragma once
// The GPU half of progressive-codec decoding (internal to ridge_render): the CPU entropy-
// decodes a child patch's residuals (ProgressiveCodec::decodeResiduals), this runs the
// reconstruction passes of shaders/progressive_reconstruct.comp, reading the parent's codes
// from one layer of a height-map array and writing the child's codes into another.
// Bit-identical to ProgressiveCodec::decode (tests/render/gpu_progressive_decoder_test.cpp).
// Needs a current GL 4.5 context.
#include "ridge/codec/level_quantizer.h"
#include "ridge/codec/progressive_reconstruction.h"
#include "ridge/gpu/gl_objects.h"
#include "ridge/gpu/shader_program.h"

#include <cstdint>

namespace ridge::render {

class GpuProgressiveDecoder {
  public:
    explicit GpuProgressiveDecoder(int patch_size);

    // `heights`: a complete GL_TEXTURE_2D_ARRAY of R16UI codes, patch_size² per layer (one
    // level, GL_NEAREST: an incomplete texture reads as zeros). The child's
    // codes land in `child_layer`; call glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT) before
    // sampling them.
    struct Child {
        int child_index = 0;      // quadrant in the parent
        LevelQuantizer quantizer; // the child level's
        OddPredictor predictor = OddPredictor::Cubic;
        CodedRegion region; // the samples the residuals cover (v1: the whole patch)
        const PredictorWeights* weights = nullptr; // v2's corrections of the level, or none
    };
    void reconstruct(const int32_t* residuals, GLuint heights, int parent_layer, int child_layer,
                     const Child& child);
    // The same from residuals stored in 16 bits (uploaded as they are, half the bytes).
    void reconstruct(const int16_t* residuals, GLuint heights, int parent_layer, int child_layer,
                     const Child& child);

  private:
    void run(int residual_bits, GLuint heights, int parent_layer, int child_layer,
             const Child& child);

    int n_;
    gpu::GlBuffer residuals_;
    gpu::GlBuffer bins_;
    gpu::ShaderProgram program_;
};

} // namespace ridge::render
