#include "allocation_counter.h"

#include <cstdlib>
#include <new>

namespace {
thread_local bool t_counting = false;
thread_local size_t t_allocations = 0;
} // namespace

// Every form is replaced, not only the two that the others call by default: a sanitizer
// runtime interposes its own nothrow and array forms, and a block from its allocator freed
// here (GDAL allocates with nothrow new) is an alloc-dealloc mismatch.
namespace {
void* counted(size_t n) noexcept
{
    if (t_counting)
        ++t_allocations;
    return std::malloc(n ? n : 1);
}
} // namespace

void* operator new(size_t n)
{
    if (void* p = counted(n))
        return p;
    throw std::bad_alloc();
}
void* operator new[](size_t n)
{
    if (void* p = counted(n))
        return p;
    throw std::bad_alloc();
}
void* operator new(size_t n, const std::nothrow_t&) noexcept
{
    return counted(n);
}
void* operator new[](size_t n, const std::nothrow_t&) noexcept
{
    return counted(n);
}
void operator delete(void* p) noexcept
{
    std::free(p);
}
void operator delete[](void* p) noexcept
{
    std::free(p);
}
void operator delete(void* p, size_t) noexcept
{
    std::free(p);
}
void operator delete[](void* p, size_t) noexcept
{
    std::free(p);
}
void operator delete(void* p, const std::nothrow_t&) noexcept
{
    std::free(p);
}
void operator delete[](void* p, const std::nothrow_t&) noexcept
{
    std::free(p);
}

namespace ridge::test {

AllocationCounter::AllocationCounter()
{
    t_allocations = 0;
    t_counting = true;
}
AllocationCounter::~AllocationCounter()
{
    t_counting = false;
}
size_t AllocationCounter::count() const
{
    return t_allocations;
}

} // namespace ridge::test
