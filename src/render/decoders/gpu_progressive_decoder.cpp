#include "gpu_progressive_decoder.h"

#include "gpu_patch_decoder.h"
#include "ridge/codec/progressive_codec.h"
#include "ridge/core/error.h"

namespace ridge::render {

GpuProgressiveDecoder::GpuProgressiveDecoder(int patch_size)
    : n_(patch_size), program_({{GL_COMPUTE_SHADER, "progressive_reconstruct.comp"}})
{
    const GLsizeiptr bytes = GLsizeiptr(n_) * n_ * GLsizeiptr(sizeof(int32_t));
    glNamedBufferStorage(residuals_.id(), bytes, nullptr, GL_DYNAMIC_STORAGE_BIT);
    glNamedBufferStorage(bins_.id(), bytes, nullptr, 0);
    gpu::checkGlError("progressive decoder: buffers");
}

void GpuProgressiveDecoder::reconstruct(const int32_t* residuals, GLuint heights, int parent_layer,
                                        int child_layer, const Child& child)
{
    glNamedBufferSubData(residuals_.id(), 0, GLsizeiptr(n_) * n_ * GLsizeiptr(sizeof(int32_t)),
                         residuals);
    run(32, heights, parent_layer, child_layer, child);
}

void GpuProgressiveDecoder::reconstruct(const int16_t* residuals, GLuint heights, int parent_layer,
                                        int child_layer, const Child& child)
{
    glNamedBufferSubData(residuals_.id(), 0, GLsizeiptr(n_) * n_ * GLsizeiptr(sizeof(int16_t)),
                         residuals);
    run(16, heights, parent_layer, child_layer, child);
}

void GpuProgressiveDecoder::run(int residual_bits, GLuint heights, int parent_layer,
                                int child_layer, const Child& child)
{
    const int child_index = child.child_index;
    const LevelQuantizer& quantizer = child.quantizer;
    const OddPredictor predictor = child.predictor;
    program_.use();
    glUniform1i(program_.uniform("u_residual_bits"), residual_bits);
    glUniform1i(program_.uniform("u_n"), n_);
    glUniform1i(program_.uniform("u_child_index"), child_index);
    glUniform1i(program_.uniform("u_parent_layer"), parent_layer);
    glUniform1i(program_.uniform("u_child_layer"), child_layer);
    glUniform1i(program_.uniform("u_step"), GLint(quantizer.step));
    glUniform1i(program_.uniform("u_bound"), quantizer.bound);
    glUniform1i(program_.uniform("u_cubic"), predictor == OddPredictor::Cubic ? 1 : 0);
    glUniform2i(program_.uniform("u_region"), child.region.width, child.region.height);
    glBindTextureUnit(0, heights);
    glBindImageTexture(1, heights, 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_R16UI);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, residuals_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, bins_.id());
    // R, A, B, C in order (each reads what the previous wrote), then the codes.
    const GLuint half = GLuint(n_ / 2 + 1), all = GLuint(n_);
    for (int pass = 0; pass <= 4; ++pass) {
        glUniform1i(program_.uniform("u_pass"), pass);
        const bool correct = child.weights && pass >= 1 && pass <= 3;
        glUniform1i(program_.uniform("u_correct"), correct ? 1 : 0);
        if (correct) {
            GLint w[kCorrectionTapCount];
            for (int i = 0; i < kCorrectionTapCount; ++i)
                w[i] = child.weights->w[pass - 1][i];
            glUniform1iv(program_.uniform("u_weights[0]"), kCorrectionTapCount, w);
        }
        const GLuint samples = pass == 4 ? all : half;
        glDispatchCompute((samples + 7) / 8, (samples + 7) / 8, 1);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    }
    gpu::checkGlError("progressive decoder: reconstruct");
}

namespace {

// The registry's face of the decoder: the child's quantizer and predictor from the codec.
class ProgressiveGpuDecoder final : public GpuPatchDecoder {
  public:
    ProgressiveGpuDecoder(const ProgressiveCodec& codec, int patch_size)
        : codec_(codec), decoder_(patch_size)
    {
    }

    void decode(const GpuPayload& payload, const Target& t, int) override
    {
        const auto& r = static_cast<const ProgressiveResiduals&>(payload);
        const GpuProgressiveDecoder::Child child{t.child_index, codec_.quantizer(t.level),
                                                 codec_.variant().predictor, r.region,
                                                 codec_.weights(t.level)};
        if (r.residuals32.empty())
            decoder_.reconstruct(r.residuals16.data(), t.heights, t.parent_layer, t.layer, child);
        else
            decoder_.reconstruct(r.residuals32.data(), t.heights, t.parent_layer, t.layer, child);
    }

  private:
    const ProgressiveCodec& codec_;
    GpuProgressiveDecoder decoder_;
};

} // namespace

GpuDecoderInfo progressiveGpuDecoder()
{
    return {
        .codec = "progressive",
        .make = [](const HeightCodec& codec, int patch_size,
                   int) -> std::unique_ptr<GpuPatchDecoder> {
            const auto* progressive = dynamic_cast<const ProgressiveCodec*>(&codec);
            if (!progressive)
                throw Error("internal error: the progressive GPU decoder given another codec");
            return std::make_unique<ProgressiveGpuDecoder>(*progressive, patch_size);
        },
        .bytes_per_slot = [](int) { return 0.0; },
    };
}

} // namespace ridge::render
