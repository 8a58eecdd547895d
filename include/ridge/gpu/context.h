#pragma once
// OpenGL 4.5 core contexts: the only place in ridge that creates them.
//
// Every GL call (ridge::gpu objects included) needs one context current on the calling thread.
// GL objects belong to the context they were created in and must be destroyed while it is
// still alive and current, so declare the context before the objects that use it. Headless and
// window contexts may be mixed on one thread; making one current releases the other.
//
// Debug output: when requested (or with RIDGE_GL_DEBUG=1 in the environment), the context is
// created with the debug flag and GL's high- and medium-severity messages go to stderr.
#include <memory>
#include <string>

struct GLFWwindow;

namespace ridge::gpu {

// An EGL context with no window, for tests, batch rendering and benchmarks. It has no default
// framebuffer: render into a RenderTarget.
class HeadlessContext {
  public:
    // Creates a 4.5 core context and makes it current on this thread. Tries, in order:
    //   1. "EGL device": EGL_EXT_platform_device (NVIDIA headless; Mesa lists a software device),
    //   2. "EGL surfaceless": EGL_MESA_platform_surfaceless,
    //   3. "EGL default display": eglGetDisplay(EGL_DEFAULT_DISPLAY) with a 1x1 pbuffer.
    // Throws ridge::Error listing every attempt and why it failed.
    static std::unique_ptr<HeadlessContext> create(bool debug = false);
    ~HeadlessContext();
    HeadlessContext(const HeadlessContext&) = delete;
    HeadlessContext& operator=(const HeadlessContext&) = delete;

    // Makes the context current on the calling thread (a context is current on one thread at a
    // time), releasing a current WindowContext first. Throws ridge::Error on failure.
    void makeCurrent();
    // GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"; read at creation, so it needs no
    // current context.
    std::string rendererName() const;
    // Which attempt of create() succeeded: "EGL device", "EGL surfaceless" or
    // "EGL default display".
    std::string platformName() const;

    struct State; // EGL handles; opaque, defined in src/gpu/headless_context.cpp

  private:
    explicit HeadlessContext(std::unique_ptr<State> state);
    std::unique_ptr<State> state_;
};

// A GLFW window with a 4.5 core context, current on the creating thread. GLFW requires that
// windows are created, polled and destroyed on the main thread.
class WindowContext {
  public:
    // `width` x `height` in screen coordinates; `vsync` sets the swap interval to 1 (else 0).
    // Throws ridge::Error when there is no display or the driver offers no GL 4.5 core.
    WindowContext(int width, int height, const std::string& title, bool vsync = true);
    ~WindowContext();
    WindowContext(const WindowContext&) = delete;
    WindowContext& operator=(const WindowContext&) = delete;

    // Makes the window's context current again (e.g. after a HeadlessContext::makeCurrent),
    // releasing a current HeadlessContext first: GLVND allows one window-system API per thread.
    void makeCurrent();
    // The GLFW window, for input callbacks; owned by this object.
    GLFWwindow* window() const { return window_; }
    bool shouldClose() const;
    void swapBuffers();
    void pollEvents();
    // Size of the default framebuffer in pixels (differs from the window size on HiDPI).
    void framebufferSize(int& width, int& height) const;
    // GL_RENDERER, read at creation.
    std::string rendererName() const { return renderer_; }

  private:
    GLFWwindow* window_ = nullptr;
    std::string renderer_;
};

} // namespace ridge::gpu
