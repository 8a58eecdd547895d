#include "ridge/gpu/gpu_timer.h"

#include "ridge/core/error.h"

#include <limits>

namespace ridge::gpu {

GpuTimer::GpuTimer() : last_ms_(std::numeric_limits<double>::quiet_NaN())
{
    queries_.reserve(kRingSize);
    for (std::size_t i = 0; i < kRingSize; ++i)
        queries_.emplace_back(GL_TIME_ELAPSED);
}

void GpuTimer::begin()
{
    if (active_)
        throw Error("GpuTimer::begin called twice without end");
    collect(false);
    if (pending_ == kRingSize)
        --pending_; // ring full: drop the oldest result (slot next_) rather than wait for it
    glBeginQuery(GL_TIME_ELAPSED, queries_[next_].id());
    active_ = true;
}

void GpuTimer::end()
{
    if (!active_)
        throw Error("GpuTimer::end called without begin");
    glEndQuery(GL_TIME_ELAPSED);
    active_ = false;
    next_ = (next_ + 1) % kRingSize;
    ++pending_;
}

double GpuTimer::lastMs() const
{
    collect(false);
    return last_ms_;
}

double GpuTimer::waitMs()
{
    collect(true);
    return last_ms_;
}

void GpuTimer::collect(bool wait) const
{
    // Queries complete in submission order, so polling stops at the first unavailable one.
    while (pending_ > 0) {
        const GLuint query = queries_[(next_ + kRingSize - pending_) % kRingSize].id();
        if (!wait) {
            GLint available = GL_FALSE;
            glGetQueryObjectiv(query, GL_QUERY_RESULT_AVAILABLE, &available);
            if (available != GL_TRUE)
                return;
        }
        GLuint64 nanoseconds = 0;
        glGetQueryObjectui64v(query, GL_QUERY_RESULT, &nanoseconds);
        last_ms_ = static_cast<double>(nanoseconds) * 1e-6;
        --pending_;
    }
}

} // namespace ridge::gpu
