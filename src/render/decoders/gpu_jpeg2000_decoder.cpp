#include "gpu_jpeg2000_decoder.h"

#include "gpu_patch_decoder.h"
#include "ridge/core/error.h"

namespace ridge::render {

GpuJpeg2000Decoder::GpuJpeg2000Decoder(int patch_size)
    : n_(patch_size), program_({{GL_COMPUTE_SHADER, "jpeg2000_residual_add.comp"}})
{
    for (auto* t : {&narrow_, &wide_}) {
        glTextureStorage2D(t->id(), 1, t == &narrow_ ? GL_R8 : GL_R16, n_, n_);
        glTextureParameteri(t->id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTextureParameteri(t->id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    }
    glNamedBufferStorage(edges_.id(), GLsizeiptr(4) * n_ * GLsizeiptr(sizeof(int32_t)), nullptr,
                         GL_DYNAMIC_STORAGE_BIT);
    gpu::checkGlError("jpeg2000 decoder: resources");
}

void GpuJpeg2000Decoder::reconstruct(const Jpeg2000Difference& d, int child_index, GLuint heights,
                                     int parent_layer, int child_layer)
{
    const bool narrow = d.bits <= 8;
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    if (narrow) {
        bytes_.assign(d.image.begin(), d.image.end());
        glTextureSubImage2D(narrow_.id(), 0, 0, 0, d.width, d.height, GL_RED, GL_UNSIGNED_BYTE,
                            bytes_.data());
    } else {
        glTextureSubImage2D(wide_.id(), 0, 0, 0, d.width, d.height, GL_RED, GL_UNSIGNED_SHORT,
                            d.image.data());
    }
    edge_values_.clear();
    for (const auto* edge : {&d.top, &d.bottom, &d.left, &d.right})
        edge_values_.insert(edge_values_.end(), edge->begin(), edge->end());
    glNamedBufferSubData(edges_.id(), 0, GLsizeiptr(edge_values_.size() * sizeof(int32_t)),
                         edge_values_.data());

    program_.use();
    glUniform1i(program_.uniform("u_n"), n_);
    glUniform1i(program_.uniform("u_child_index"), child_index);
    glUniform1i(program_.uniform("u_parent_layer"), parent_layer);
    glUniform1i(program_.uniform("u_child_layer"), child_layer);
    glUniform1i(program_.uniform("u_direct"), d.kind == Jpeg2000Encoding::Direct ? 1 : 0);
    glUniform1i(program_.uniform("u_d_min"), d.d_min);
    glUniform1i(program_.uniform("u_step"), GLint(d.step));
    glUniform1i(program_.uniform("u_unorm_max"), narrow ? 255 : 65535);
    glUniform2i(program_.uniform("u_region"), d.width, d.height);
    glBindTextureUnit(0, heights);
    glBindImageTexture(1, heights, 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_R16UI);
    glBindTextureUnit(2, narrow ? narrow_.id() : wide_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, edges_.id());
    glDispatchCompute(GLuint(n_ + 7) / 8, GLuint(n_ + 7) / 8, 1);
    gpu::checkGlError("jpeg2000 decoder: residual add");
}

namespace {

class Jpeg2000GpuDecoder final : public GpuPatchDecoder {
  public:
    explicit Jpeg2000GpuDecoder(int patch_size) : decoder_(patch_size) {}

    void decode(const GpuPayload& payload, const Target& t, int) override
    {
        decoder_.reconstruct(static_cast<const Jpeg2000Difference&>(payload), t.child_index,
                             t.heights, t.parent_layer, t.layer);
    }

  private:
    GpuJpeg2000Decoder decoder_;
};

} // namespace

GpuDecoderInfo jpeg2000GpuDecoder()
{
    return {
        .codec = "jpeg2000",
        .make = [](const HeightCodec& codec, int patch_size,
                   int) -> std::unique_ptr<GpuPatchDecoder> {
            if (!dynamic_cast<const Jpeg2000Codec*>(&codec))
                throw Error("internal error: the jpeg2000 GPU decoder given another codec");
            return std::make_unique<Jpeg2000GpuDecoder>(patch_size);
        },
        .bytes_per_slot = [](int) { return 0.0; },
    };
}

} // namespace ridge::render
