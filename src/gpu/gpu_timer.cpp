#include "ridge/gpu/gpu_timer.h"

#include "ridge/core/error.h"

#include <limits>

namespace ridge::gpu {

GpuTimer::GpuTimer() : spans_(kRingSize), last_ms_(std::numeric_limits<double>::quiet_NaN()) {}

void GpuTimer::begin()
{
    if (active_)
        throw Error("GpuTimer::begin called twice without end");
    collect(false);
    if (pending_ == kRingSize)
        --pending_; // ring full: drop the oldest result (slot next_) rather than wait for it
    Span& span = spans_[next_];
    span.begun = Clock::now();
    glQueryCounter(span.start.id(), GL_TIMESTAMP);
    active_ = true;
}

void GpuTimer::end()
{
    if (!active_)
        throw Error("GpuTimer::end called without begin");
    glQueryCounter(spans_[next_].stop.id(), GL_TIMESTAMP);
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
    // Queries complete in submission order, so polling stops at the first unavailable one
    // (a span's stop comes after its start).
    while (pending_ > 0) {
        const Span& span = spans_[(next_ + kRingSize - pending_) % kRingSize];
        if (!wait) {
            GLint available = GL_FALSE;
            glGetQueryObjectiv(span.stop.id(), GL_QUERY_RESULT_AVAILABLE, &available);
            if (available != GL_TRUE)
                return;
        }
        GLuint64 start_ns = 0, stop_ns = 0;
        glGetQueryObjectui64v(span.start.id(), GL_QUERY_RESULT, &start_ns);
        glGetQueryObjectui64v(span.stop.id(), GL_QUERY_RESULT, &stop_ns);
        const double wall_ms =
            std::chrono::duration<double, std::milli>(Clock::now() - span.begun).count();
        const double ms = static_cast<double>(stop_ns - start_ns) * 1e-6;
        last_ms_ =
            stop_ns >= start_ns && ms <= wall_ms ? ms : std::numeric_limits<double>::quiet_NaN();
        --pending_;
    }
}

} // namespace ridge::gpu
