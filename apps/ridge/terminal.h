#pragma once
// Terminal plumbing shared by the subcommands: GDAL-style progress on stderr, Ctrl-C.
#include "ridge/core/progress.h"

namespace ridge::cli {

// Installs SIGINT/SIGTERM handlers that make every progress callback ask to cancel, so that
// outputs are cleaned up instead of being left half-written.
void installInterruptHandler();
bool interrupted();

// "0...10...20...30...40...50...60...70...80...90...100 - done." like GDAL's tools, or
// silent (but still cancellable) with quiet = true.
Progress terminalProgress(bool quiet);

} // namespace ridge::cli
