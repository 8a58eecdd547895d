#include "gpu_test.h"
#include "ridge/gpu/gl_objects.h"
#include "ridge/gpu/gpu_timer.h"
#include "ridge/gpu/render_target.h"

#include <cmath>

using namespace ridge;
using namespace ridge::gpu;
using ridge::gpu::test::GpuTest;

namespace {

void clearOnce(const RenderTarget& target)
{
    target.bind();
    glClearColor(0.5f, 0.5f, 0.5f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
}

} // namespace

TEST_F(GpuTest, GpuTimerIsNaNBeforeTheFirstResult)
{
    GpuTimer timer;
    EXPECT_TRUE(std::isnan(timer.lastMs()));
    EXPECT_TRUE(std::isnan(timer.waitMs()));
}

TEST_F(GpuTest, GpuTimerWaitMsIsFiniteAndNonNegative)
{
    RenderTarget target(64, 64);
    GpuTimer timer;
    timer.begin();
    clearOnce(target);
    timer.end();
    const double ms = timer.waitMs();
    EXPECT_TRUE(std::isfinite(ms)) << ms;
    EXPECT_GE(ms, 0.0);
    EXPECT_EQ(timer.lastMs(), ms); // nothing newer has ended
    checkGlError("timer queries");
}

TEST_F(GpuTest, GpuTimerKeepsMeasuringPastItsRingWithoutWaiting)
{
    RenderTarget target(16, 16);
    GpuTimer timer;
    for (std::size_t frame = 0; frame < 3 * GpuTimer::kRingSize; ++frame) {
        timer.begin();
        clearOnce(target);
        timer.end();
        (void)timer.lastMs(); // may be NaN for the first frames; must not stall or throw
    }
    const double ms = timer.waitMs();
    EXPECT_TRUE(std::isfinite(ms) && ms >= 0.0) << ms;
    checkGlError("timer ring");
}

TEST_F(GpuTest, GpuTimerRejectsUnbalancedBeginAndEnd)
{
    GpuTimer timer;
    EXPECT_THROW(timer.end(), Error);
    timer.begin();
    EXPECT_THROW(timer.begin(), Error);
    timer.end();
}
