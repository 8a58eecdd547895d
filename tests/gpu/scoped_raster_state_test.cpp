#include "gpu_test.h"
#include "ridge/core/error.h"
#include "ridge/gpu/render_target.h"
#include "ridge/gpu/scoped_raster_state.h"

#include <array>

using namespace ridge;
using namespace ridge::gpu;
using ridge::gpu::test::GpuTest;

namespace {

std::array<GLint, 4> four(GLenum name)
{
    std::array<GLint, 4> v{};
    glGetIntegerv(name, v.data());
    return v;
}

GLint one(GLenum name)
{
    GLint v = 0;
    glGetIntegerv(name, &v);
    return v;
}

// A pass that changes everything the guard promises to put back, and may throw half-way.
void pass(GLuint framebuffer, bool throws)
{
    const ScopedRasterState saved;
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, framebuffer);
    glViewport(0, 0, 3, 3);
    glScissor(1, 1, 1, 1);
    glBlendEquation(GL_MAX);
    glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    for (GLenum s : ScopedRasterState::kSwitches)
        (glIsEnabled(s) ? glDisable : glEnable)(s);
    if (throws)
        throw Error("the pass failed");
}

} // namespace

TEST_F(GpuTest, AScopedRasterStatePutsBackWhatAPassChangedThrownOrNot)
{
    RenderTarget host(8, 8, 1), other(4, 4, 1);
    for (const bool throws : {false, true}) {
        host.bind();
        glViewport(1, 2, 5, 6);
        glScissor(2, 3, 4, 5);
        glBlendEquationSeparate(GL_FUNC_SUBTRACT, GL_MIN);
        glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
        glEnable(GL_BLEND);
        glEnable(GL_SCISSOR_TEST);
        glDisable(GL_DEPTH_TEST);
        glEnable(GL_CULL_FACE);
        glDisable(GL_RASTERIZER_DISCARD);
        const GLint framebuffer = one(GL_DRAW_FRAMEBUFFER_BINDING);
        try {
            pass(other.framebuffer(), throws);
            EXPECT_FALSE(throws);
        } catch (const Error&) {
            EXPECT_TRUE(throws);
        }
        EXPECT_EQ(one(GL_DRAW_FRAMEBUFFER_BINDING), framebuffer);
        EXPECT_EQ(four(GL_VIEWPORT), (std::array<GLint, 4>{1, 2, 5, 6}));
        EXPECT_EQ(four(GL_SCISSOR_BOX), (std::array<GLint, 4>{2, 3, 4, 5}));
        EXPECT_EQ(one(GL_BLEND_EQUATION_RGB), GL_FUNC_SUBTRACT);
        EXPECT_EQ(one(GL_BLEND_EQUATION_ALPHA), GL_MIN);
        EXPECT_EQ(one(GL_POLYGON_MODE), GL_LINE);
        EXPECT_TRUE(glIsEnabled(GL_BLEND));
        EXPECT_TRUE(glIsEnabled(GL_SCISSOR_TEST));
        EXPECT_FALSE(glIsEnabled(GL_DEPTH_TEST));
        EXPECT_TRUE(glIsEnabled(GL_CULL_FACE));
        EXPECT_FALSE(glIsEnabled(GL_RASTERIZER_DISCARD));
        EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
        glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    }
}
