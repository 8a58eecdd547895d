#include "ridge/gpu/primitive_counter.h"

namespace ridge::gpu {

PrimitiveCounter::PrimitiveCounter() : pending_(kRingSize, false)
{
    for (std::size_t k = 0; k < kRingSize; ++k)
        queries_.emplace_back(GL_PRIMITIVES_GENERATED);
}

void PrimitiveCounter::begin()
{
    current_ = next_;
    next_ = (current_ + 1) % kRingSize;
    glBeginQuery(GL_PRIMITIVES_GENERATED, queries_[current_].id());
}

void PrimitiveCounter::end()
{
    glEndQuery(GL_PRIMITIVES_GENERATED);
    pending_[current_] = true;
}

std::uint64_t PrimitiveCounter::latest()
{
    // Oldest first (the query the next begin() takes is the oldest), so the newest available
    // result wins.
    for (std::size_t k = 0; k < kRingSize; ++k) {
        const std::size_t q = (next_ + k) % kRingSize;
        if (!pending_[q])
            continue;
        GLuint available = 0;
        glGetQueryObjectuiv(queries_[q].id(), GL_QUERY_RESULT_AVAILABLE, &available);
        if (!available)
            continue;
        GLuint64 generated = 0;
        glGetQueryObjectui64v(queries_[q].id(), GL_QUERY_RESULT, &generated);
        last_ = generated;
        pending_[q] = false;
    }
    return last_;
}

std::uint64_t PrimitiveCounter::wait()
{
    GLuint64 generated = 0;
    glGetQueryObjectui64v(queries_[current_].id(), GL_QUERY_RESULT, &generated);
    pending_[current_] = false;
    last_ = generated;
    return last_;
}

} // namespace ridge::gpu
