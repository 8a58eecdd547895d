// Embedding ridge's renderer in an application's own OpenGL 4.5 core context. A real
// application has a window (GLFW, SDL, Qt); this one makes a headless EGL context and draws
// into its own framebuffer object, then checks the terrain covered the picture.
//   ridge_embed_gl ARCHIVE.ridge
#include <ridge/ridge.h>

#include <epoxy/egl.h>
#include <epoxy/gl.h>

#include <cstdio>
#include <vector>

namespace {

// A current OpenGL 4.5 core context without a window: Mesa's surfaceless platform, else the
// default display with a 1x1 pbuffer. Returns false when neither works.
bool makeHeadlessContext()
{
    EGLDisplay display = EGL_NO_DISPLAY;
    bool pbuffer = false;
    // The EXT entry point: EGL 1.5's eglGetPlatformDisplay needs a display to ask for the
    // version, which there is not yet.
    if (epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_EXT_platform_base") &&
        epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_MESA_platform_surfaceless"))
        display = eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (display == EGL_NO_DISPLAY || !eglInitialize(display, nullptr, nullptr)) {
        display = eglGetDisplay(EGL_DEFAULT_DISPLAY);
        pbuffer = true;
        if (display == EGL_NO_DISPLAY || !eglInitialize(display, nullptr, nullptr))
            return false;
    }
    const EGLint config_attributes[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE,
                                        pbuffer ? EGL_PBUFFER_BIT : 0, EGL_NONE};
    EGLConfig config = nullptr;
    EGLint count = 0;
    if (!eglBindAPI(EGL_OPENGL_API) ||
        !eglChooseConfig(display, config_attributes, &config, 1, &count) || count == 0)
        return false;
    const EGLint context_attributes[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5,
                                         EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                         EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
    const EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, context_attributes);
    if (context == EGL_NO_CONTEXT)
        return false;
    EGLSurface surface = EGL_NO_SURFACE;
    if (pbuffer) {
        const EGLint size[] = {EGL_WIDTH, 1, EGL_HEIGHT, 1, EGL_NONE};
        surface = eglCreatePbufferSurface(display, config, size);
    }
    return eglMakeCurrent(display, surface, surface, context) == EGL_TRUE;
}

} // namespace

int main(int argc, char** argv)
{
    if (argc != 2) {
        std::fprintf(stderr, "usage: %s ARCHIVE.ridge\n", argv[0]);
        return 2;
    }
    if (!makeHeadlessContext()) {
        std::fprintf(stderr, "ridge_embed_gl: no OpenGL 4.5 core context through EGL\n");
        return 1;
    }
    const int width = 320, height = 180;
    // The application's framebuffer: colour and a depth buffer (ridge draws reverse-Z and
    // needs 24 bits or more).
    GLuint fbo = 0, colour = 0, depth = 0;
    glGenRenderbuffers(1, &colour);
    glBindRenderbuffer(GL_RENDERBUFFER, colour);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
    glGenRenderbuffers(1, &depth);
    glBindRenderbuffer(GL_RENDERBUFFER, depth);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, width, height);
    glGenFramebuffers(1, &fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, colour);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
        std::fprintf(stderr, "ridge_embed_gl: incomplete framebuffer\n");
        return 1;
    }
    glViewport(0, 0, width, height);

    try {
        ridge::RendererParameters parameters;
        parameters.streaming = false; // every patch loaded before the frame that needs it
        parameters.schemes = {"tess", "chunked", "geomorph"};
        ridge::Renderer renderer(argv[1], parameters);
        const ridge::CameraPose camera = renderer.defaultCamera(width, height);
        ridge::FrameSummary frame{};
        for (const char* scheme : {"tess", "chunked", "geomorph"}) {
            ridge::DrawParameters draw;
            draw.scheme = scheme;
            frame = renderer.draw(camera, width, height, draw);
            std::printf("%s: %d patches, %llu triangles, ε %.2f px\n", scheme, frame.patches,
                        (unsigned long long)frame.triangles, frame.screen_error_px);
        }
        // The default camera frames the whole terrain (about a fifth of this picture for the
        // Everest crop): terrain pixels have a reverse-Z depth above the cleared 0.
        std::vector<float> z(size_t(width) * height);
        glReadPixels(0, 0, width, height, GL_DEPTH_COMPONENT, GL_FLOAT, z.data());
        size_t terrain = 0;
        for (float d : z)
            terrain += d > 0.f;
        std::printf("terrain covers %.1f %% of the picture\n", 100.0 * terrain / z.size());
        if (frame.patches < 1 || terrain < z.size() / 10) {
            std::fprintf(stderr, "ridge_embed_gl: the terrain was not drawn\n");
            return 1;
        }
    } catch (const ridge::Error& e) {
        std::fprintf(stderr, "ridge_embed_gl: %s\n", e.what());
        return 1;
    }
    return 0;
}
