#pragma once
// Counts this thread's calls of global operator new between construction and destruction:
// the steady-state "no allocation per frame" checks. The replacement operators live in
// allocation_counter.cpp, a translation unit of their own so that no caller inlines them
// (GCC would then see malloc'd memory freed by delete); they cover the whole test
// executable, but only count while a counter lives on the calling thread.
#include <cstddef>

namespace ridge::test {

class AllocationCounter {
  public:
    AllocationCounter();
    ~AllocationCounter();
    AllocationCounter(const AllocationCounter&) = delete;
    AllocationCounter& operator=(const AllocationCounter&) = delete;
    size_t count() const; // allocations since construction
};

} // namespace ridge::test
