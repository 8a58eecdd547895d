#pragma once
// Primitives a span of draws generated (GL_PRIMITIVES_GENERATED: what the tessellator or the
// vertex stage produced), counted for interactive use with a ring of queries read only once
// their results are available, so counting never stalls the pipeline; or, for headless single
// frames and tests, waited for.
#include "ridge/gpu/gl_objects.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace ridge::gpu {

// Needs a current GL context for its whole life (see context.h).
class PrimitiveCounter {
  public:
    static constexpr std::size_t kRingSize = 4;

    PrimitiveCounter();
    // Starts counting the primitives of the draws issued until end(). A still-pending query
    // in the slot it takes is dropped: its span is kRingSize spans old.
    void begin();
    void end();
    // The count of the newest span whose result the GPU has delivered; 0 before the first.
    // Never stalls (only polls GL_QUERY_RESULT_AVAILABLE).
    std::uint64_t latest();
    // Blocks until the span just ended has its count, and returns it.
    std::uint64_t wait();

  private:
    std::vector<GlQuery> queries_; // kRingSize
    std::vector<bool> pending_;    // per query: ended, result unread
    std::size_t next_ = 0;         // the query the next begin() takes
    std::size_t current_ = 0;      // the query of the span begun last
    std::uint64_t last_ = 0;       // the newest count read
};

} // namespace ridge::gpu
