#pragma once
#include <functional>

namespace ridge {

// Progress callback: receives completed fraction in [0, 1]; returns false to cancel.
// Long operations call it from the thread that called them, never concurrently.
using Progress = std::function<bool(double fraction)>;

// Calls `progress` (if any) and throws Cancelled when it asks to stop.
void reportProgress(const Progress& progress, double fraction);

// Reports completion (1.0) once the output is published: a cancel request that arrives now
// is ignored, since there is nothing left to undo (throwing would claim that no output was
// written while it is already in place).
void reportDone(const Progress& progress);

// Maps [0,1] of a sub-step onto [begin, end] of the parent's progress.
Progress subProgress(const Progress& parent, double begin, double end);

} // namespace ridge
