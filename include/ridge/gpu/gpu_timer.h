#pragma once
// GPU time of a span of GL commands, measured with GL_TIME_ELAPSED queries.
#include "ridge/gpu/gl_objects.h"

#include <cstddef>
#include <vector>

namespace ridge::gpu {

// A ring of kRingSize queries so that a frame's result can be read a few frames later without
// stalling. GL_TIME_ELAPSED queries cannot nest: at most one timer may be between begin() and
// end() at any time. Needs a current GL context for its whole life (see context.h).
class GpuTimer {
public:
    static constexpr std::size_t kRingSize = 4;

    GpuTimer();
    // Starts timing the commands issued until end(). If all kRingSize queries are still in
    // flight, the oldest result is dropped (never waited for). Throws ridge::Error when already
    // begun.
    void begin();
    // Stops timing. Throws ridge::Error without a matching begin().
    void end();
    // The most recent result the GPU has already delivered, in milliseconds; NaN before the
    // first. Never stalls (only polls GL_QUERY_RESULT_AVAILABLE).
    double lastMs() const;
    // Blocks until the most recently ended query has its result and returns it in
    // milliseconds (for headless single frames); NaN when no query has ended yet.
    double waitMs();

private:
    // Reads results of in-flight queries, oldest first; blocks for all of them when `wait`.
    void collect(bool wait) const;

    std::vector<GlQuery> queries_; // kRingSize GL_TIME_ELAPSED queries
    std::size_t next_ = 0;         // slot the next begin() uses
    bool active_ = false;          // between begin() and end()
    // Ended queries whose result is unread: the `pending_` slots just before next_.
    mutable std::size_t pending_ = 0;
    mutable double last_ms_; // NaN until the first result
};

} // namespace ridge::gpu
