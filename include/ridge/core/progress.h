#pragma once
#include <functional>

namespace ridge {

// Progress callback: receives completed fraction in [0, 1]; returns false to cancel.
// Long operations call it from the thread that called them, never concurrently.
using Progress = std::function<bool(double fraction)>;

// Calls `progress` (if any) and throws Cancelled when it asks to stop.
void reportProgress(const Progress& progress, double fraction);

// Maps [0,1] of a sub-step onto [begin, end] of the parent's progress.
Progress subProgress(const Progress& parent, double begin, double end);

} // namespace ridge
