#include "gpu_test.h"
#include "ridge/gpu/gl_objects.h"
#include "ridge/gpu/render_target.h"
#include "ridge/gpu/shader_program.h"

#include <array>
#include <cstdlib>

using namespace ridge;
using namespace ridge::gpu;
using ridge::gpu::test::GpuTest;

namespace {

using Rgba = std::array<int, 4>;

Rgba pixel(const std::vector<uint8_t>& rgba, const RenderTarget& target, int row, int column)
{
    const std::size_t at = (static_cast<std::size_t>(row) * target.width() + column) * 4;
    return {rgba[at], rgba[at + 1], rgba[at + 2], rgba[at + 3]};
}

// Draws test/quadrants.frag over the whole target: red right half, green top half (in GL's
// bottom-left-origin window space), depth `top_depth` in the top half and 0.75 below.
void drawQuadrants(const RenderTarget& target, float top_depth)
{
    ShaderProgram program(
        {{GL_VERTEX_SHADER, "test/fullscreen.vert"}, {GL_FRAGMENT_SHADER, "test/quadrants.frag"}});
    GlVertexArray vao;
    target.bind();
    glClearColor(0.0f, 0.0f, 0.0f, 0.0f);
    glClearDepth(1.0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_ALWAYS);
    program.use();
    glUniform2f(program.uniform("u_size"), static_cast<float>(target.width()),
                static_cast<float>(target.height()));
    glUniform1f(program.uniform("u_depth_top"), top_depth);
    glUniform1f(program.uniform("u_depth_bottom"), 0.75f);
    glBindVertexArray(vao.id());
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glDisable(GL_DEPTH_TEST);
    checkGlError("drawing quadrants");
}

// Every pixel has the quadrant colour and depth drawQuadrants gives it, with row 0 the top.
void expectQuadrants(const RenderTarget& target, float top_depth)
{
    const std::vector<uint8_t> rgba = target.readRgba();
    const std::vector<float> depth = target.readDepth();
    ASSERT_EQ(rgba.size(), static_cast<std::size_t>(target.width() * target.height() * 4));
    ASSERT_EQ(depth.size(), static_cast<std::size_t>(target.width() * target.height()));
    int wrong = 0;
    for (int row = 0; row < target.height(); ++row) {
        for (int column = 0; column < target.width(); ++column) {
            const bool top = row < target.height() / 2;
            const bool right = column >= target.width() / 2;
            const Rgba expected = {right ? 255 : 0, top ? 255 : 0, 64, 255};
            const Rgba got = pixel(rgba, target, row, column);
            const float got_depth = depth[static_cast<std::size_t>(row) * target.width() + column];
            bool ok = got_depth == (top ? top_depth : 0.75f);
            for (int c = 0; c < 4; ++c)
                ok = ok && std::abs(got[c] - expected[c]) <= 1;
            if (!ok && ++wrong <= 5)
                ADD_FAILURE() << "row " << row << " column " << column << ": rgba " << got[0] << ","
                              << got[1] << "," << got[2] << "," << got[3] << " depth " << got_depth;
        }
    }
    EXPECT_EQ(wrong, 0);
}

} // namespace

TEST_F(GpuTest, ClearFillsEveryPixelWithTheClearColour)
{
    RenderTarget target(8, 4);
    EXPECT_EQ(target.width(), 8);
    EXPECT_EQ(target.height(), 4);
    target.bind();
    glClearColor(0.2f, 0.4f, 0.6f, 1.0f);
    glClearDepth(0.5);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    const std::vector<uint8_t> rgba = target.readRgba();
    for (int row = 0; row < 4; ++row) {
        for (int column = 0; column < 8; ++column) {
            const Rgba got = pixel(rgba, target, row, column);
            EXPECT_NEAR(got[0], 51, 1);
            EXPECT_NEAR(got[1], 102, 1);
            EXPECT_NEAR(got[2], 153, 1);
            EXPECT_EQ(got[3], 255);
        }
    }
    for (float d : target.readDepth())
        EXPECT_EQ(d, 0.5f);
}

TEST_F(GpuTest, FullScreenTriangleReadsBackWithTheTopRowFirst)
{
    RenderTarget target(16, 8);
    drawQuadrants(target, 0.25f);
    expectQuadrants(target, 0.25f);
}

TEST_F(GpuTest, MultisampledTargetIsResolvedForReadback)
{
    RenderTarget target(16, 8, 4);
    EXPECT_NE(target.framebuffer(), 0u);
    drawQuadrants(target, 0.125f);
    expectQuadrants(target, 0.125f);
}

TEST_F(GpuTest, RenderTargetRejectsBadSizesAndSampleCounts)
{
    EXPECT_THROW(RenderTarget(0, 8), Error);
    EXPECT_THROW(RenderTarget(8, -1), Error);
    EXPECT_THROW(RenderTarget(1 << 30, 8), Error);
    EXPECT_THROW(RenderTarget(8, 8, 0), Error);
    EXPECT_THROW(RenderTarget(8, 8, 1 << 20), Error);
}
