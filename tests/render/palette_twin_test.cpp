// shaders/palette.glsl and ridge::palette (ridge/core/terrain_palette.h) give the same colours:
// the renderer and `ridge hillshade` paint one palette. The GLSL only interpolates the C++
// tables it is sent (render::setPaletteUniforms); this checks that it does so identically, at
// many heights across land, the coast and the sea, and for the debug modes' colours.
#include "palette_uniforms.h"

#include "ridge/core/terrain_palette.h"
#include "ridge/gpu/context.h"
#include "ridge/gpu/gl_objects.h"
#include "ridge/gpu/shader_program.h"

#include <glm/vec4.hpp>
#include <gtest/gtest.h>

#include <random>

using namespace ridge;

TEST(PaletteTwin, ShaderAndCppPaintTheSameColoursAtManyHeights)
{
    auto context = gpu::HeadlessContext::create();
    const gpu::ShaderProgram program({{GL_COMPUTE_SHADER, "test/palette_twin.comp"}});
    render::setPaletteUniforms(program);
    std::mt19937 rng(13);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    // Terrains with and without sea: ETOPO-like, a coast from 0 m, an inland massif.
    const std::array<std::array<float, 2>, 3> ranges = {
        {{-10376.f, 7833.f}, {0.f, 4300.f}, {3369.f, 8840.f}}};
    std::vector<glm::vec4> cases;
    for (int k = 0; k < 8192; ++k) {
        const auto [lo, hi] = ranges[size_t(k) % ranges.size()];
        // Every tenth case right at sea level, the others anywhere in (and a bit beyond) range.
        const float h = k % 10 == 0 ? 0.f : lo + (hi - lo) * (1.2f * u(rng) - 0.1f);
        cases.push_back({h, lo, hi, 1.2f * u(rng) - 0.1f});
    }
    const int count = int(cases.size());
    gpu::GlBuffer in, out;
    glNamedBufferStorage(in.id(), GLsizeiptr(cases.size() * sizeof(glm::vec4)), cases.data(), 0);
    glNamedBufferStorage(out.id(), GLsizeiptr(3 * cases.size() * sizeof(glm::vec4)), nullptr, 0);
    program.use();
    glUniform1i(program.uniform("u_case_count"), count);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, in.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, out.id());
    glDispatchCompute(GLuint(count + 63) / 64, 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::vector<glm::vec4> gpu(3 * cases.size());
    glGetNamedBufferSubData(out.id(), 0, GLsizeiptr(gpu.size() * sizeof(glm::vec4)), gpu.data());
    gpu::checkGlError("palette twin");

    int water = 0;
    auto near = [](palette::Rgb c, glm::vec4 g) {
        return std::abs(c.r - g.x) < 1e-5f && std::abs(c.g - g.y) < 1e-5f &&
               std::abs(c.b - g.z) < 1e-5f;
    };
    for (int i = 0; i < count; ++i) {
        const glm::vec4 c = cases[size_t(i)];
        const bool flagged = palette::isWater(c.x) || i % 3 == 0; // as palette_twin.comp
        const palette::Rgb terrain = palette::terrainColour(c.x, flagged, c.y, c.z);
        EXPECT_TRUE(near(terrain, gpu[3 * size_t(i)]))
            << "height " << c.x << " m on [" << c.y << ", " << c.z << "]: C++ " << terrain.r << ","
            << terrain.g << "," << terrain.b << ", GLSL " << gpu[3 * size_t(i)].x << ","
            << gpu[3 * size_t(i)].y << "," << gpu[3 * size_t(i)].z;
        EXPECT_EQ(palette::isWater(c.x), gpu[3 * size_t(i)].w > 0.5f) << c.x;
        water += palette::isWater(c.x);
        EXPECT_TRUE(near(palette::heat(c.w), gpu[3 * size_t(i) + 1])) << "heat t " << c.w;
        EXPECT_TRUE(near(palette::levelColour(int(c.x) & 1023), gpu[3 * size_t(i) + 2])) << c.x;
    }
    EXPECT_GT(water, count / 8) << "the cases must cover the sea";
    EXPECT_LT(water, count / 2) << "... and the land";
}
