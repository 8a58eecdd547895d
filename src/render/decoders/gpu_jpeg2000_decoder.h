#pragma once
// The GPU residual add of the JPEG2000 paper (§4), internal to ridge_render: the CPU decodes
// a patch's difference layer (Jpeg2000Codec::decodeDifference); this uploads D̂ as an 8-bit
// (or, for wider layers, 16-bit) normalized texture and runs shaders/jpeg2000_residual_add.comp,
// which adds it, scaled, to the bilinear prediction from the parent's codes in one layer of a
// height-map array and writes the child's codes into another. Bit-identical to
// Jpeg2000Codec::decode (tests/render/gpu_jpeg2000_decoder_test.cpp). Needs a current GL 4.5
// context. The streamer drives it through the GPU decoder registry (gpu_patch_decoder.h).
#include "ridge/codec/jpeg2000_codec.h"
#include "ridge/gpu/gl_objects.h"
#include "ridge/gpu/shader_program.h"

namespace ridge::render {

class GpuJpeg2000Decoder {
  public:
    explicit GpuJpeg2000Decoder(int patch_size);

    // `heights`: a complete GL_TEXTURE_2D_ARRAY of R16UI codes, patch_size² per layer. Call
    // glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT) before sampling the child.
    void reconstruct(const Jpeg2000Difference& d, int child_index, GLuint heights, int parent_layer,
                     int child_layer);

  private:
    int n_;
    gpu::GlTexture narrow_{GL_TEXTURE_2D}; // R8: n <= 8 bits, the paper's case
    gpu::GlTexture wide_{GL_TEXTURE_2D};   // R16: 9..16 bits
    gpu::GlBuffer edges_;
    gpu::ShaderProgram program_;
    std::vector<uint8_t> bytes_;
    std::vector<int32_t> edge_values_;
};

} // namespace ridge::render
