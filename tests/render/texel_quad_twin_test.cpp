// shaders/texel_quad.glsl (terrain.frag's heights and water flags at fractional patch
// coordinates, by one textureGather) against a CPU bilinear of the same texels: exact at every
// sample, including the far border and clamped coordinates, and the right neighbours between
// them (a gather's component order is easy to get wrong: rows or columns swapped still pass
// any test that only looks at a coastline).
#include "ridge/gpu/context.h"
#include "ridge/gpu/gl_objects.h"
#include "ridge/gpu/shader_program.h"

#include <glm/vec4.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

using namespace ridge;

TEST(TexelQuadTwin, GatheredBilinearEqualsTheCpuBilinearOfTheSameTexels)
{
    auto context = gpu::HeadlessContext::create();
    const int cells = 8, n = cells + 1, layers = 3;
    std::mt19937 rng(29);
    std::vector<uint16_t> texels(size_t(n * n * layers));
    for (uint16_t& t : texels)
        t = uint16_t(rng() % 65536);
    auto texel = [&](int i, int j, int layer) {
        return double(texels[size_t((layer * n + j) * n + i)]);
    };
    gpu::GlTexture map(GL_TEXTURE_2D_ARRAY);
    glTextureStorage3D(map.id(), 1, GL_R16UI, n, n, layers);
    // Rows of 9 shorts are not 4-byte aligned: unpack them as they are.
    glPixelStorei(GL_UNPACK_ALIGNMENT, 2);
    glTextureSubImage3D(map.id(), 0, 0, 0, 0, n, n, layers, GL_RED_INTEGER, GL_UNSIGNED_SHORT,
                        texels.data());
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTextureParameteri(map.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(map.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);

    // Every sample, then fractional points, then points beyond the border (clamped).
    std::uniform_real_distribution<float> u(0.f, 1.f);
    std::vector<glm::vec4> cases;
    for (int layer = 0; layer < layers; ++layer)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i)
                cases.push_back({float(i), float(j), float(layer), 0.f});
    const size_t samples = cases.size();
    for (int k = 0; k < 2000; ++k)
        cases.push_back({cells * u(rng), cells * u(rng), float(rng() % layers), 0.f});
    for (int k = 0; k < 200; ++k)
        cases.push_back({cells * (3.f * u(rng) - 1.f), cells * (3.f * u(rng) - 1.f),
                         float(rng() % layers), 0.f});

    const gpu::ShaderProgram program({{GL_COMPUTE_SHADER, "test/texel_quad_twin.comp"}});
    const int count = int(cases.size());
    gpu::GlBuffer in, out;
    glNamedBufferStorage(in.id(), GLsizeiptr(cases.size() * sizeof(glm::vec4)), cases.data(), 0);
    glNamedBufferStorage(out.id(), GLsizeiptr(cases.size() * sizeof(float)), nullptr, 0);
    program.use();
    glUniform1i(program.uniform("u_case_count"), count);
    glUniform1i(program.uniform("u_cells"), cells);
    glBindTextureUnit(0, map.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, in.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, out.id());
    glDispatchCompute(GLuint(count + 63) / 64, 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::vector<float> gpu(cases.size());
    glGetNamedBufferSubData(out.id(), 0, GLsizeiptr(gpu.size() * sizeof(float)), gpu.data());
    gpu::checkGlError("texel quad twin");

    for (size_t k = 0; k < cases.size(); ++k) {
        const glm::vec4 c = cases[k];
        const double x = std::clamp(double(c.x), 0.0, double(cells));
        const double y = std::clamp(double(c.y), 0.0, double(cells));
        const int i0 = std::min(int(std::floor(x)), cells - 1);
        const int j0 = std::min(int(std::floor(y)), cells - 1);
        const double fx = x - i0, fy = y - j0;
        const int layer = int(c.z);
        const double cpu =
            (1 - fy) * ((1 - fx) * texel(i0, j0, layer) + fx * texel(i0 + 1, j0, layer)) +
            fy * ((1 - fx) * texel(i0, j0 + 1, layer) + fx * texel(i0 + 1, j0 + 1, layer));
        if (k < samples)
            ASSERT_EQ(double(gpu[k]), cpu)
                << "sample (" << c.x << ", " << c.y << ") of layer " << layer;
        else
            ASSERT_NEAR(double(gpu[k]), cpu, 0.05)
                << "at (" << c.x << ", " << c.y << ") of layer " << layer;
    }
}
