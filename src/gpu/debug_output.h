#pragma once
// GL debug output shared by HeadlessContext and WindowContext (internal to ridge_gpu).

namespace ridge::gpu::detail {

// True when RIDGE_GL_DEBUG=1 is set in the environment.
bool debugRequestedByEnv();

// With the context current: routes GL's high- and medium-severity debug messages to stderr,
// synchronously (so a breakpoint in the callback shows the offending call). Needs GL 4.3+.
void installDebugOutput();

// Throws ridge::Error unless the current context is GL >= 4.5 core; `what` names the context.
void requireGl45Core(const char* what);

} // namespace ridge::gpu::detail
