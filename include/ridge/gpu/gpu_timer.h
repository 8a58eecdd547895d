#pragma once
// GPU time of a span of GL commands, measured with a pair of GL_TIMESTAMP queries
// (glQueryCounter) at its ends.
//
// Not GL_TIME_ELAPSED: Mesa's llvmpipe starts an elapsed-time query only when the span bins
// a draw, so a span of texture uploads and compute dispatches alone read back the end
// timestamp itself — the time since boot (`render --json` reported gpu_upload_ms = 619,384
// for a 1 s run). Two timestamps are each taken when the GPU reaches them, draws or not.
// A result longer than the wall time from begin() to its read-back is impossible (the GPU ran
// both ends inside that interval) and reads as NaN, "not measured", never as a number.
#include "ridge/gpu/gl_objects.h"

#include <chrono>
#include <cstddef>
#include <vector>

namespace ridge::gpu {

// A ring of kRingSize query pairs so that a frame's result can be read a few frames later
// without stalling. Needs a current GL context for its whole life (see context.h).
class GpuTimer {
  public:
    static constexpr std::size_t kRingSize = 4;

    GpuTimer();
    // Starts timing the commands issued until end(). If all kRingSize pairs are still in
    // flight, the oldest result is dropped (never waited for). Throws ridge::Error when already
    // begun.
    void begin();
    // Stops timing. Throws ridge::Error without a matching begin().
    void end();
    // The most recent result the GPU has already delivered, in milliseconds; NaN before the
    // first. Never stalls (only polls GL_QUERY_RESULT_AVAILABLE).
    double lastMs() const;
    // Blocks until the most recently ended span has its result and returns it in
    // milliseconds (for headless single frames); NaN when no span has ended yet.
    double waitMs();

  private:
    using Clock = std::chrono::steady_clock;
    struct Span {
        GlQuery start{GL_TIMESTAMP};
        GlQuery stop{GL_TIMESTAMP};
        Clock::time_point begun; // CPU time of begin(): the bound on the result
    };

    // Reads results of in-flight spans, oldest first; blocks for all of them when `wait`.
    void collect(bool wait) const;

    std::vector<Span> spans_; // kRingSize query pairs
    std::size_t next_ = 0;    // slot the next begin() uses
    bool active_ = false;     // between begin() and end()
    // Ended spans whose result is unread: the `pending_` slots just before next_.
    mutable std::size_t pending_ = 0;
    mutable double last_ms_; // NaN until the first result
};

} // namespace ridge::gpu
