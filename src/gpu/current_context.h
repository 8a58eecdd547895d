#pragma once
// GLVND lets a thread have a current context of one window-system API at a time: glXMakeCurrent
// fails with BadAccess while an EGL context is current, and vice versa. Before making a context
// of one API current, release the other's (internal to ridge_gpu).

namespace ridge::gpu::detail {

// Makes no EGL context current on this thread (no-op when none is). In headless_context.cpp.
void releaseCurrentEglContext();
// Makes no GLFW (GLX) context current on this thread (no-op when none is, or no window exists).
// In window_context.cpp.
void releaseCurrentGlfwContext();

} // namespace ridge::gpu::detail
