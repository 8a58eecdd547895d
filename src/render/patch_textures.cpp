#include "patch_textures.h"

#include <algorithm>

namespace ridge::render {

PatchTextures::PatchTextures(int patch_size, const TessellationBlockLayout& layout, int levels,
                             int slots, const HeightQuantization& quantization)
    : n_(patch_size), layout_(layout), levels_(levels), quantization_(quantization),
      lambda_max_(size_t(slots), 0.f)
{
    const int B = layout_.blocksPerSide();
    glTextureStorage3D(heights_.id(), 1, GL_R16UI, n_, n_, slots);
    glTextureParameteri(heights_.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(heights_.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTextureStorage3D(normals_.id(), 1, GL_RGBA8_SNORM, n_, n_, slots);
    glTextureParameteri(normals_.id(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTextureParameteri(normals_.id(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(normals_.id(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(normals_.id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glTextureStorage3D(block_errors_.id(), 1, GL_RGBA32F, B, B, slots);
    glTextureParameteri(block_errors_.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(block_errors_.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTextureStorage2D(bordered_.id(), 1, GL_R32F, n_ + 2, n_ + 2);
    glTextureParameteri(bordered_.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(bordered_.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    gpu::checkGlError("patch textures: texture arrays");
    normal_program_ = gpu::ShaderProgram({{GL_COMPUTE_SHADER, "patch_normals.comp"}});
}

void PatchTextures::upload(const stream::DecodedPatch& patch, int slot,
                           const std::vector<float>& bordered, double cell_metres_i,
                           double cell_metres_j, float lambda_cap)
{
    // Rows of 2^n + 1 16-bit codes are not 4-byte aligned.
    glPixelStorei(GL_UNPACK_ALIGNMENT, 2);
    glTextureSubImage3D(heights_.id(), 0, 0, 0, slot, n_, n_, 1, GL_RED_INTEGER, GL_UNSIGNED_SHORT,
                        patch.codes.data());
    // λ(d) as one RGBA texel per block; missing levels (D < 4) stay 0 and are never read.
    const int B = layout_.blocksPerSide(), D = layout_.levels();
    std::vector<float> texels(size_t(B) * B * 4, 0.f);
    for (int b = 0; b < B * B; ++b)
        for (int d = 0; d < levels_; ++d)
            texels[size_t(b) * 4 + d] = patch.block_errors[size_t(b) * D + d];
    glTextureSubImage3D(block_errors_.id(), 0, 0, 0, slot, B, B, 1, GL_RGBA, GL_FLOAT,
                        texels.data());
    // The tessellator drops at most λ max; λ never exceeds the patch's height range (every
    // simplified vertex is a patch sample), which also tames saturated values.
    const float lambda_max = *std::max_element(texels.begin(), texels.end());
    lambda_max_[size_t(slot)] = std::min(lambda_max, lambda_cap);

    // Normal map on the GPU, from the heights with a ring from the same-level neighbours.
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTextureSubImage2D(bordered_.id(), 0, 0, 0, n_ + 2, n_ + 2, GL_RED, GL_FLOAT, bordered.data());
    normal_program_.use();
    glBindTextureUnit(0, bordered_.id());
    glBindImageTexture(0, normals_.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA8_SNORM);
    glUniform1i(normal_program_.uniform("u_layer"), slot);
    glUniform1i(normal_program_.uniform("u_size"), n_);
    glUniform2f(normal_program_.uniform("u_cell_metres"), float(cell_metres_i),
                float(cell_metres_j));
    glUniform1f(normal_program_.uniform("u_height_scale"), float(quantization_.scale));
    glDispatchCompute(GLuint(n_ + 7) / 8, GLuint(n_ + 7) / 8, 1);
}

void PatchTextures::finishUploads() const
{
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
}

void PatchTextures::bind() const
{
    glBindTextureUnit(0, heights_.id());
    glBindTextureUnit(1, normals_.id());
    glBindTextureUnit(2, block_errors_.id());
}

} // namespace ridge::render
