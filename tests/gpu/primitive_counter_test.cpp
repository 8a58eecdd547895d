#include "gpu_test.h"
#include "ridge/gpu/gl_objects.h"
#include "ridge/gpu/primitive_counter.h"
#include "ridge/gpu/render_target.h"
#include "ridge/gpu/shader_program.h"

#include <cstdint>

using namespace ridge;
using namespace ridge::gpu;
using ridge::gpu::test::GpuTest;

namespace {

// Draws `triangles` triangles (test/fullscreen.vert over and over) into `target`, counted.
void drawCounted(PrimitiveCounter& counter, const RenderTarget& target,
                 const ShaderProgram& program, const GlVertexArray& vao, int triangles)
{
    target.bind();
    program.use();
    glBindVertexArray(vao.id());
    counter.begin();
    glDrawArrays(GL_TRIANGLES, 0, 3 * triangles);
    counter.end();
}

} // namespace

TEST_F(GpuTest, PrimitiveCounterIsZeroBeforeTheFirstResult)
{
    PrimitiveCounter counter;
    EXPECT_EQ(counter.latest(), 0u);
}

TEST_F(GpuTest, PrimitiveCounterWaitsForItsSpanAndOtherwiseReportsTheNewestAvailableCount)
{
    RenderTarget target(16, 16);
    const ShaderProgram program(
        {{GL_VERTEX_SHADER, "test/fullscreen.vert"}, {GL_FRAGMENT_SHADER, "test/quadrants.frag"}});
    const GlVertexArray vao;
    PrimitiveCounter counter;
    drawCounted(counter, target, program, vao, 5);
    EXPECT_EQ(counter.wait(), 5u);
    EXPECT_EQ(counter.latest(), 5u); // nothing newer has ended

    // A whole ring of spans, none read: once all are done, the newest one's count wins.
    for (int k = 1; k <= int(PrimitiveCounter::kRingSize); ++k)
        drawCounted(counter, target, program, vao, k);
    glFinish();
    EXPECT_EQ(counter.latest(), std::uint64_t(PrimitiveCounter::kRingSize));

    // Past the ring without reading never stalls, and waiting still gives the span just ended.
    for (int k = 1; k <= 3 * int(PrimitiveCounter::kRingSize); ++k) {
        drawCounted(counter, target, program, vao, k);
        (void)counter.latest();
    }
    drawCounted(counter, target, program, vao, 7);
    EXPECT_EQ(counter.wait(), 7u);
    checkGlError("primitive counter");
}
