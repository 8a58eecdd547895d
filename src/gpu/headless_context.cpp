// HeadlessContext: EGL without a window. The three display kinds are tried in order of how
// likely they are to give a hardware context on a machine without a display server.
#include "ridge/gpu/context.h"

#include "current_context.h"
#include "debug_output.h"
#include "ridge/core/error.h"

#include <epoxy/egl.h>
#include <epoxy/gl.h>

#include <string>
#include <vector>

namespace ridge::gpu {
namespace {

std::string eglErrorName(EGLint error)
{
    switch (error) {
    case EGL_SUCCESS:
        return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED:
        return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS:
        return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC:
        return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE:
        return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG:
        return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT:
        return "EGL_BAD_CONTEXT";
    case EGL_BAD_CURRENT_SURFACE:
        return "EGL_BAD_CURRENT_SURFACE";
    case EGL_BAD_DISPLAY:
        return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH:
        return "EGL_BAD_MATCH";
    case EGL_BAD_NATIVE_PIXMAP:
        return "EGL_BAD_NATIVE_PIXMAP";
    case EGL_BAD_NATIVE_WINDOW:
        return "EGL_BAD_NATIVE_WINDOW";
    case EGL_BAD_PARAMETER:
        return "EGL_BAD_PARAMETER";
    case EGL_BAD_SURFACE:
        return "EGL_BAD_SURFACE";
    case EGL_CONTEXT_LOST:
        return "EGL_CONTEXT_LOST";
    default:
        return "EGL error " + std::to_string(error);
    }
}

// "<call> failed (<EGL error>)", for the attempt log.
Error eglFailure(const std::string& call)
{
    return Error(call + " failed (" + eglErrorName(eglGetError()) + ")");
}

bool hasExtension(EGLDisplay display, const char* name)
{
    // epoxy parses the space-separated list; EGL_NO_DISPLAY queries client extensions.
    return epoxy_has_egl_extension(display, name);
}

std::vector<EGLint> contextAttributes(bool egl15, bool debug)
{
    // EGL 1.5 names; the EGL_KHR_create_context tokens have the same values, except debug,
    // which KHR spells as a flag bit.
    std::vector<EGLint> attributes = {
        EGL_CONTEXT_MAJOR_VERSION,       4,
        EGL_CONTEXT_MINOR_VERSION,       5,
        EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT};
    if (debug && egl15) {
        attributes.insert(attributes.end(), {EGL_CONTEXT_OPENGL_DEBUG, EGL_TRUE});
    } else if (debug) {
        attributes.insert(attributes.end(),
                          {EGL_CONTEXT_FLAGS_KHR, EGL_CONTEXT_OPENGL_DEBUG_BIT_KHR});
    }
    attributes.push_back(EGL_NONE);
    return attributes;
}

} // namespace

// Displays are initialised once and never terminated: EGL displays are per process (one per
// native display), so eglTerminate would end every other context on it, and it unloads the
// driver, whose allocations then show up as unattributable leaks under LeakSanitizer.
struct HeadlessContext::State {
    EGLDisplay display;
    EGLContext context = EGL_NO_CONTEXT;
    EGLSurface surface = EGL_NO_SURFACE; // 1x1 pbuffer, or none when surfaceless
    std::string platform;
    std::string renderer;

    explicit State(EGLDisplay d) : display(d) {}
    State(const State&) = delete;
    State& operator=(const State&) = delete;
    ~State()
    {
        const EGLDisplay d = display;
        if (context != EGL_NO_CONTEXT && eglGetCurrentContext() == context)
            eglMakeCurrent(d, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        if (surface != EGL_NO_SURFACE)
            eglDestroySurface(d, surface);
        if (context != EGL_NO_CONTEXT)
            eglDestroyContext(d, context);
    }
};

namespace {

// A current 4.5 core context on `display`, or an Error saying why not. `pbuffer`: render
// surface is a 1x1 pbuffer instead of none (also used when EGL_KHR_surfaceless_context lacks).
std::unique_ptr<HeadlessContext::State> openOn(EGLDisplay display, const char* platform,
                                               bool pbuffer, bool debug)
{
    if (display == EGL_NO_DISPLAY)
        throw eglFailure("getting the display");
    EGLint major = 0;
    EGLint minor = 0;
    if (!eglInitialize(display, &major, &minor))
        throw eglFailure("eglInitialize");
    auto state = std::make_unique<HeadlessContext::State>(display);
    state->platform = platform;

    const bool egl15 = major > 1 || minor >= 5;
    const std::string version = "EGL " + std::to_string(major) + "." + std::to_string(minor);
    if (!egl15 && !hasExtension(display, "EGL_KHR_create_context"))
        throw Error(version + " without EGL_KHR_create_context");
    pbuffer = pbuffer || !hasExtension(display, "EGL_KHR_surfaceless_context");
    if (!eglBindAPI(EGL_OPENGL_API))
        throw eglFailure("eglBindAPI(EGL_OPENGL_API)");

    const EGLint config_attributes[] = {EGL_RENDERABLE_TYPE,
                                        EGL_OPENGL_BIT,
                                        EGL_SURFACE_TYPE,
                                        pbuffer ? EGL_PBUFFER_BIT : 0,
                                        EGL_RED_SIZE,
                                        8,
                                        EGL_GREEN_SIZE,
                                        8,
                                        EGL_BLUE_SIZE,
                                        8,
                                        EGL_NONE};
    EGLConfig config = nullptr;
    EGLint config_count = 0;
    if (!eglChooseConfig(display, config_attributes, &config, 1, &config_count))
        throw eglFailure("eglChooseConfig");
    if (config_count == 0)
        throw Error(version + ": no RGB8 config with desktop OpenGL" +
                    (pbuffer ? " and pbuffers" : ""));

    const std::vector<EGLint> context_attributes = contextAttributes(egl15, debug);
    state->context = eglCreateContext(display, config, EGL_NO_CONTEXT, context_attributes.data());
    if (state->context == EGL_NO_CONTEXT)
        throw eglFailure(version + " eglCreateContext(OpenGL 4.5 core)");
    if (pbuffer) {
        const EGLint surface_attributes[] = {EGL_WIDTH, 1, EGL_HEIGHT, 1, EGL_NONE};
        state->surface = eglCreatePbufferSurface(display, config, surface_attributes);
        if (state->surface == EGL_NO_SURFACE)
            throw eglFailure("eglCreatePbufferSurface(1x1)");
    }
    detail::releaseCurrentGlfwContext();
    if (!eglMakeCurrent(display, state->surface, state->surface, state->context))
        throw eglFailure("eglMakeCurrent");

    detail::requireGl45Core(platform);
    const auto* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    state->renderer = renderer ? renderer : "(unknown renderer)";
    if (debug)
        detail::installDebugOutput();
    return state;
}

std::unique_ptr<HeadlessContext::State> openOnDevices(bool debug, std::string& log)
{
    if (!hasExtension(EGL_NO_DISPLAY, "EGL_EXT_platform_device") ||
        !hasExtension(EGL_NO_DISPLAY, "EGL_EXT_device_enumeration")) {
        log += "\n  EGL device: EGL_EXT_platform_device/EGL_EXT_device_enumeration unsupported";
        return nullptr;
    }
    EGLint count = 0;
    if (!eglQueryDevicesEXT(0, nullptr, &count) || count <= 0) {
        log += "\n  EGL device: no devices (" + eglErrorName(eglGetError()) + ")";
        return nullptr;
    }
    std::vector<EGLDeviceEXT> devices(static_cast<size_t>(count));
    eglQueryDevicesEXT(count, devices.data(), &count);
    for (EGLint i = 0; i < count; ++i) {
        try {
            const EGLDisplay display =
                eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr);
            return openOn(display, "EGL device", false, debug);
        } catch (const Error& e) {
            log += "\n  EGL device " + std::to_string(i) + ": " + e.what();
        }
    }
    return nullptr;
}

std::unique_ptr<HeadlessContext::State> openSurfaceless(bool debug, std::string& log)
{
    if (!hasExtension(EGL_NO_DISPLAY, "EGL_MESA_platform_surfaceless")) {
        log += "\n  EGL surfaceless: EGL_MESA_platform_surfaceless unsupported";
        return nullptr;
    }
    try {
        const EGLDisplay display =
            eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
        return openOn(display, "EGL surfaceless", false, debug);
    } catch (const Error& e) {
        log += std::string("\n  EGL surfaceless: ") + e.what();
        return nullptr;
    }
}

std::unique_ptr<HeadlessContext::State> openDefaultDisplay(bool debug, std::string& log)
{
    try {
        return openOn(eglGetDisplay(EGL_DEFAULT_DISPLAY), "EGL default display", true, debug);
    } catch (const Error& e) {
        log += std::string("\n  EGL default display: ") + e.what();
        return nullptr;
    }
}

} // namespace

HeadlessContext::HeadlessContext(std::unique_ptr<State> state) : state_(std::move(state)) {}

HeadlessContext::~HeadlessContext() = default;

std::unique_ptr<HeadlessContext> HeadlessContext::create(bool debug)
{
    debug = debug || detail::debugRequestedByEnv();
    std::string log;
    std::unique_ptr<State> state = openOnDevices(debug, log);
    if (!state)
        state = openSurfaceless(debug, log);
    if (!state)
        state = openDefaultDisplay(debug, log);
    if (!state)
        throw Error("no headless OpenGL 4.5 core context; tried:" + log);
    return std::unique_ptr<HeadlessContext>(new HeadlessContext(std::move(state)));
}

void HeadlessContext::makeCurrent()
{
    if (!eglBindAPI(EGL_OPENGL_API))
        throw eglFailure("eglBindAPI(EGL_OPENGL_API)");
    detail::releaseCurrentGlfwContext();
    if (!eglMakeCurrent(state_->display, state_->surface, state_->surface, state_->context))
        throw eglFailure("eglMakeCurrent");
}

void detail::releaseCurrentEglContext()
{
    if (eglGetCurrentContext() != EGL_NO_CONTEXT)
        eglMakeCurrent(eglGetCurrentDisplay(), EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
}

std::string HeadlessContext::rendererName() const
{
    return state_->renderer;
}

std::string HeadlessContext::platformName() const
{
    return state_->platform;
}

} // namespace ridge::gpu
