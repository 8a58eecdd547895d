#pragma once
// Terminal plumbing shared by the subcommands: GDAL-style progress on stderr, interrupts.
#include "ridge/core/progress.h"

namespace ridge::cli {

// SIGINT (Ctrl-C), SIGTERM (kill, systemd, timeout(1)) and SIGHUP (terminal closed) make
// every progress callback ask to cancel, so that the operation unwinds and its AtomicOutput
// removes the temporary file. The handler resets itself: a second signal of the same kind
// terminates at once, which leaves nothing behind either (the temporary file is unnamed or
// locked, see atomic_output.h). Signals ignored when the process started (nohup, background
// jobs of a non-interactive shell) stay ignored.
// SIGXFSZ (a file size limit, ulimit -f) is ignored, so that the write fails with EFBIG and
// the ordinary error path reports "File too large" and cleans up instead of a core dump.
void installInterruptHandler();
bool interrupted();
// "SIGTERM" etc. for messages.
const char* interruptSignalName();

// Ends the process after a cancelled operation has cleaned up, the way a shell expects of a
// process stopped by that signal: the default action is restored and the signal re-raised,
// so the parent sees WIFSIGNALED (exit status 128 + N in a shell: 130 for SIGINT, 143 for
// SIGTERM, 129 for SIGHUP). A shell running a loop stops it only then. Falls back to
// exit(128 + N) if the signal does not terminate, and returns 130 without a signal.
int exitAfterInterrupt();

// "0...10...20...30...40...50...60...70...80...90...100 - done." like GDAL's tools, or
// silent (but still cancellable) with quiet = true.
Progress terminalProgress(bool quiet);

} // namespace ridge::cli
