// WindowContext: a GLFW window. GLFW is initialised with the first window and terminated with
// the last, since glfwTerminate destroys every window.
#include "ridge/gpu/context.h"

#include "current_context.h"
#include "debug_output.h"
#include "ridge/core/error.h"

#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE // GL declarations come from epoxy
#include <GLFW/glfw3.h>

#include <string>

namespace ridge::gpu {
namespace {

// GLFW reports failures through a callback; the latest one goes into the thrown message.
thread_local std::string glfw_last_error;

void recordGlfwError(int code, const char* description)
{
    glfw_last_error = description ? description : "GLFW error " + std::to_string(code);
}

int window_count = 0; // live WindowContexts; GLFW calls are main-thread only, so no lock

void acquireGlfw()
{
    glfwSetErrorCallback(recordGlfwError);
    if (window_count == 0 && glfwInit() != GLFW_TRUE)
        throw Error("cannot open a window: " + glfw_last_error +
                    " (no display? headless code "
                    "should use HeadlessContext)");
    ++window_count;
}

void releaseGlfw()
{
    if (--window_count == 0)
        glfwTerminate();
}

} // namespace

WindowContext::WindowContext(int width, int height, const std::string& title, bool vsync)
{
    glfw_last_error.clear();
    acquireGlfw();
    const bool debug = detail::debugRequestedByEnv();
    glfwDefaultWindowHints();
    glfwWindowHint(GLFW_CLIENT_API, GLFW_OPENGL_API);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_OPENGL_DEBUG_CONTEXT, debug ? GLFW_TRUE : GLFW_FALSE);
    // glfwCreateWindow makes the new context current to read its attributes.
    detail::releaseCurrentEglContext();
    window_ = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
    if (window_ == nullptr) {
        releaseGlfw();
        throw Error("cannot create a " + std::to_string(width) + "x" + std::to_string(height) +
                    " window with OpenGL 4.5 core: " + glfw_last_error);
    }
    makeCurrent();
    try {
        detail::requireGl45Core("GLFW window");
    } catch (...) {
        glfwDestroyWindow(window_);
        releaseGlfw();
        throw;
    }
    glfwSwapInterval(vsync ? 1 : 0);
    const auto* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    renderer_ = renderer ? renderer : "(unknown renderer)";
    if (debug)
        detail::installDebugOutput();
}

WindowContext::~WindowContext()
{
    glfwDestroyWindow(window_);
    releaseGlfw();
}

void WindowContext::makeCurrent()
{
    detail::releaseCurrentEglContext();
    glfwMakeContextCurrent(window_);
}

void detail::releaseCurrentGlfwContext()
{
    if (window_count > 0 && glfwGetCurrentContext() != nullptr)
        glfwMakeContextCurrent(nullptr);
}

bool WindowContext::shouldClose() const
{
    return glfwWindowShouldClose(window_) == GLFW_TRUE;
}

void WindowContext::swapBuffers()
{
    glfwSwapBuffers(window_);
}

void WindowContext::pollEvents()
{
    glfwPollEvents();
}

void WindowContext::framebufferSize(int& width, int& height) const
{
    glfwGetFramebufferSize(window_, &width, &height);
}

} // namespace ridge::gpu
