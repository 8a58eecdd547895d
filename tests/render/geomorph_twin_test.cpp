// shaders/geomorph_common.glsl and ridge::lod's geomorph packers agree: compact vertices,
// drawn from real attributes in the documented formats block by block, decode on the GPU to
// the positions the CPU computes (bit for bit) and to the hemisphere normals it encoded.
#include "ridge/gpu/context.h"
#include "ridge/gpu/gl_objects.h"
#include "ridge/gpu/render_target.h"
#include "ridge/gpu/shader_program.h"
#include "ridge/lod/geomorph.h"
#include "ridge/lod/hemisphere_normals.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>

#include <cmath>
#include <random>
#include <vector>

using namespace ridge;

namespace {

struct Captured {
    float position[3];
    float normal_analytic[3];
    float normal_texture[3];
};
static_assert(sizeof(Captured) == 36);

glm::dvec3 textureNormal(const std::vector<uint8_t>& texture, uint8_t u, uint8_t v)
{
    const uint8_t* t = &texture[4 * (size_t(v) * lod::kHemisphereTextureSize + u)];
    const glm::dvec3 n(2.0 * t[0] / 255 - 1, 2.0 * t[1] / 255 - 1, 2.0 * t[2] / 255 - 1);
    return n / std::sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
}

} // namespace

TEST(GeomorphTwin, CompactVerticesDecodeOnTheGpuAsTheCppPackersComputeThem)
{
    auto context = gpu::HeadlessContext::create();
    const gpu::ShaderProgram program({{GL_VERTEX_SHADER, "test/geomorph_twin.vert"}},
                                     {"position", "normal_analytic", "normal_texture"});
    const int n = 257; // 2×2 blocks of 128 cells
    std::mt19937 rng(5);
    std::uniform_int_distribution<int> noise(-300, 300);
    std::vector<uint16_t> parent(size_t(n) * n), own(size_t(n) * n);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const double base = 20000 + 8000 * std::sin(i * 0.05) * std::cos(j * 0.04);
            parent[size_t(j) * n + i] = uint16_t(base + noise(rng));
            own[size_t(j) * n + i] = uint16_t(base + 0.5 * noise(rng));
        }
    std::vector<double> target(own.size());
    lod::targetHeights(parent.data(), n, 1, 0, target.data());
    const lod::GeomorphFrame frame{0.1234, -731.25, 37.5, 22.0};
    std::vector<float> normals(3 * own.size());
    lod::patchNormals(own.data(), n, frame, normals.data());
    const lod::GeomorphPatchData patch{n, own.data(), target.data(), normals.data()};
    const size_t count = lod::geomorphVertexCount(n);
    const int blocks = lod::geomorphBlocksPerSide(n), b = lod::geomorphBlockCells(n);
    const size_t per_block = size_t(b + 1) * (b + 1);
    std::vector<lod::CompactBlock> records(size_t(blocks) * blocks);
    lod::buildCompactBlocks(n, 0, records.data());

    const gpu::RenderTarget render_target(1, 1); // a complete framebuffer for the draws
    render_target.bind();
    for (lod::HemisphereMap map :
         {lod::HemisphereMap::Orthographic, lod::HemisphereMap::Concentric}) {
        const double t = map == lod::HemisphereMap::Orthographic ? 0.3125 : 0.7;
        std::vector<lod::CompactVertex> compact(count);
        lod::packCompact(patch, map, lod::GeomorphShading::Lit, compact.data());
        std::vector<lod::StandardVertex> standard(count);
        lod::packStandard(patch, frame, t, lod::GeomorphShading::Lit, standard.data());
        const std::vector<uint8_t> texels = lod::buildHemisphereNormalTexture(map);

        gpu::GlTexture texture(GL_TEXTURE_2D);
        glTextureStorage2D(texture.id(), 1, GL_RGBA8, 256, 256);
        glTextureSubImage2D(texture.id(), 0, 0, 0, 256, 256, GL_RGBA, GL_UNSIGNED_BYTE,
                            texels.data());
        glTextureParameteri(texture.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTextureParameteri(texture.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        glTextureParameteri(texture.id(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glTextureParameteri(texture.id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
        glBindTextureUnit(3, texture.id());

        gpu::GlBuffer vertices, captured;
        glNamedBufferStorage(vertices.id(), GLsizeiptr(count * sizeof(lod::CompactVertex)),
                             compact.data(), 0);
        glNamedBufferStorage(captured.id(), GLsizeiptr(count * sizeof(Captured)), nullptr, 0);
        gpu::GlVertexArray vao;
        glVertexArrayVertexBuffer(vao.id(), 0, vertices.id(), 0, sizeof(lod::CompactVertex));
        for (GLuint a : {0u, 1u, 2u}) {
            glEnableVertexArrayAttrib(vao.id(), a);
            glVertexArrayAttribBinding(vao.id(), a, 0);
        }
        glVertexArrayAttribIFormat(vao.id(), 0, 2, GL_UNSIGNED_BYTE,
                                   offsetof(lod::CompactVertex, bx));
        glVertexArrayAttribIFormat(vao.id(), 1, 2, GL_UNSIGNED_SHORT,
                                   offsetof(lod::CompactVertex, height));
        glVertexArrayAttribFormat(vao.id(), 2, 2, GL_UNSIGNED_BYTE, GL_FALSE,
                                  offsetof(lod::CompactVertex, normal_u));
        glBindVertexArray(vao.id());

        program.use();
        glUniform1f(program.uniform("u_geomorph_height_scale"), float(frame.scale));
        glUniform1f(program.uniform("u_geomorph_height_offset"), float(frame.offset));
        glUniform2f(program.uniform("u_geomorph_cell"), float(frame.cell_x), float(frame.cell_y));
        glUniform1i(program.uniform("u_hemisphere_map"), int(map));
        glUniform1f(program.uniform("u_morph"), float(t));
        gpu::GlTransformFeedback feedback;
        glTransformFeedbackBufferBase(feedback.id(), 0, captured.id());
        glEnable(GL_RASTERIZER_DISCARD);
        glBindTransformFeedback(GL_TRANSFORM_FEEDBACK, feedback.id());
        glBeginTransformFeedback(GL_POINTS);
        for (size_t k = 0; k < records.size(); ++k) { // the block identifier once per block
            const lod::CompactBlock& r = records[k];
            glUniform4i(program.uniform("u_geomorph_block"), r.origin_i, r.origin_j, r.patch,
                        r.block_cells);
            glDrawArrays(GL_POINTS, GLint(k * per_block), GLsizei(per_block));
        }
        glEndTransformFeedback();
        glDisable(GL_RASTERIZER_DISCARD);
        glBindTransformFeedback(GL_TRANSFORM_FEEDBACK, 0);
        gpu::checkGlError("geomorph twin draw");
        std::vector<Captured> gpu(count);
        glGetNamedBufferSubData(captured.id(), 0, GLsizeiptr(count * sizeof(Captured)), gpu.data());

        int z_mismatches = 0;
        double worst_texture = 0, worst_analytic = 0;
        for (size_t k = 0; k < count; ++k) {
            const lod::CompactVertex& c = compact[k];
            const Captured& g = gpu[k];
            // x, y: the same sample and rounding as packStandard, bit for bit.
            ASSERT_EQ(g.position[0], standard[k].x) << k;
            ASSERT_EQ(g.position[1], standard[k].y) << k;
            // z from the 16-bit codes: the C++ morph of the same codes, bit for bit ...
            const float z = lod::morphHeight(lod::geomorphMetres(frame, c.height),
                                             lod::geomorphMetres(frame, c.target), float(t));
            z_mismatches += g.position[2] != z;
            // ... and within ½ code·t of the CPU-morphed exact target.
            ASSERT_LE(std::abs(g.position[2] - standard[k].z), 0.5 * frame.scale * t + 1e-3) << k;
            const glm::dvec3 exact(lod::decodeHemisphereNormal(map, c.normal_u, c.normal_v));
            const glm::dvec3 analytic(g.normal_analytic[0], g.normal_analytic[1],
                                      g.normal_analytic[2]);
            const glm::dvec3 fetched(g.normal_texture[0], g.normal_texture[1], g.normal_texture[2]);
            worst_analytic = std::max(worst_analytic, glm::length(analytic - exact));
            worst_texture =
                std::max(worst_texture,
                         glm::length(fetched - textureNormal(texels, c.normal_u, c.normal_v)));
        }
        EXPECT_EQ(z_mismatches, 0) << "of " << count << " vertices";
        EXPECT_LT(worst_analytic, 1e-5);
        EXPECT_LT(worst_texture, 1e-5);
    }
}
