// Embedding ridge's renderer in an application's own OpenGL 4.5 core context. A real
// application has a window (GLFW, SDL, Qt); this one makes a headless EGL context and draws
// into its own framebuffer object, then checks what it drew:
//   1. a frame with ridge's own camera (every LOD scheme): the terrain covers the picture;
//   2. the application's scene: its own camera matrices (GL's default depth conventions), its
//      own object — a 50 m pole through the highest summit — and the terrain drawn into the
//      same framebuffer without clearing, so that each hides the other where it is nearer;
//   3. a pick through the summit's pixel: the terrain point under it, with lon/lat.
//   ridge_embed_gl ARCHIVE.ridge
#include <ridge/ridge.h>

#include <epoxy/egl.h>
#include <epoxy/gl.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

namespace {

using Mat4 = std::array<double, 16>; // column-major, as GL and ridge::HostView take them
using Vec3 = std::array<double, 3>;

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
        display =
            eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
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
    const EGLint context_attributes[] = {EGL_CONTEXT_MAJOR_VERSION,
                                         4,
                                         EGL_CONTEXT_MINOR_VERSION,
                                         5,
                                         EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                         EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                         EGL_NONE};
    const EGLContext context =
        eglCreateContext(display, config, EGL_NO_CONTEXT, context_attributes);
    if (context == EGL_NO_CONTEXT)
        return false;
    EGLSurface surface = EGL_NO_SURFACE;
    if (pbuffer) {
        const EGLint size[] = {EGL_WIDTH, 1, EGL_HEIGHT, 1, EGL_NONE};
        surface = eglCreatePbufferSurface(display, config, size);
    }
    return eglMakeCurrent(display, surface, surface, context) == EGL_TRUE;
}

// The application's own matrices (what glm::lookAt and glm::perspective make).
Mat4 lookAt(const Vec3& eye, const Vec3& target)
{
    Vec3 f{target[0] - eye[0], target[1] - eye[1], target[2] - eye[2]};
    const double lf = std::sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
    for (double& v : f)
        v /= lf;
    Vec3 s{f[1], -f[0], 0.0}; // f × up, up = +z
    const double ls = std::sqrt(s[0] * s[0] + s[1] * s[1]);
    s = {s[0] / ls, s[1] / ls, 0.0};
    const Vec3 u{s[1] * f[2] - s[2] * f[1], s[2] * f[0] - s[0] * f[2], s[0] * f[1] - s[1] * f[0]};
    auto dot = [](const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; };
    return {s[0], u[0], -f[0], 0, s[1],         u[1],         -f[1],       0,
            s[2], u[2], -f[2], 0, -dot(s, eye), -dot(u, eye), dot(f, eye), 1};
}

Mat4 perspective(double fov_y_degrees, double aspect, double n, double f)
{
    const double t = 1.0 / std::tan(fov_y_degrees * 3.14159265358979323846 / 360.0);
    return {
        t / aspect, 0, 0, 0, 0, t, 0, 0, 0, 0, -(f + n) / (f - n), -1, 0, 0, -2.0 * f * n / (f - n),
        0};
}

// Window pixel (x right, y down) of world point p.
void project(const Mat4& view, const Mat4& proj, int width, int height, const Vec3& p, double& x,
             double& y)
{
    double e[4], c[4];
    for (int r = 0; r < 4; ++r)
        e[r] = view[r] * p[0] + view[4 + r] * p[1] + view[8 + r] * p[2] + view[12 + r];
    for (int r = 0; r < 4; ++r)
        c[r] = proj[r] * e[0] + proj[4 + r] * e[1] + proj[8 + r] * e[2] + proj[12 + r] * e[3];
    x = (c[0] / c[3] * 0.5 + 0.5) * width;
    y = (0.5 - c[1] / c[3] * 0.5) * height;
}

// The application's own object: a solid box in one colour, with its own shader.
class Box {
  public:
    Box()
    {
        const char* vs = "#version 450 core\nlayout(location = 0) in vec3 p;\n"
                         "uniform mat4 m;\nvoid main() { gl_Position = m * vec4(p, 1.0); }\n";
        const char* fs = "#version 450 core\nout vec4 c;\n"
                         "void main() { c = vec4(1.0, 0.0, 1.0, 1.0); }\n";
        program_ = glCreateProgram();
        for (auto [kind, source] :
             {std::pair{GL_VERTEX_SHADER, vs}, std::pair{GL_FRAGMENT_SHADER, fs}}) {
            const GLuint s = glCreateShader(kind);
            glShaderSource(s, 1, &source, nullptr);
            glCompileShader(s);
            glAttachShader(program_, s);
            glDeleteShader(s);
        }
        glLinkProgram(program_);
        glCreateVertexArrays(1, &vao_);
        glCreateBuffers(1, &buffer_);
        glNamedBufferStorage(buffer_, 36 * 3 * sizeof(float), nullptr, GL_DYNAMIC_STORAGE_BIT);
        glVertexArrayVertexBuffer(vao_, 0, buffer_, 0, 3 * sizeof(float));
        glEnableVertexArrayAttrib(vao_, 0);
        glVertexArrayAttribFormat(vao_, 0, 3, GL_FLOAT, GL_FALSE, 0);
        glVertexArrayAttribBinding(vao_, 0, 0);
    }
    // World coordinates here are ridge's local metres (tens of km): the corners are made
    // relative to the eye in double, and drawn with the view's rotation alone, so that
    // float vertices keep centimetres (ridge draws its terrain the same way).
    void draw(const Mat4& view, const Mat4& proj, const Vec3& lo, const Vec3& hi) const
    {
        Vec3 eye{};
        for (int i = 0; i < 3; ++i)
            eye[i] =
                -(view[i * 4] * view[12] + view[i * 4 + 1] * view[13] + view[i * 4 + 2] * view[14]);
        Mat4 rotation = view;
        rotation[12] = rotation[13] = rotation[14] = 0.0;
        float m[16];
        for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 4; ++r) {
                double sum = 0.0;
                for (int k = 0; k < 4; ++k)
                    sum += proj[k * 4 + r] * rotation[c * 4 + k];
                m[c * 4 + r] = float(sum);
            }
        std::vector<float> v;
        const int faces[6][4] = {{0, 2, 6, 4}, {1, 3, 7, 5}, {0, 1, 5, 4},
                                 {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 5, 7, 6}};
        for (const auto& f : faces)
            for (int k : {f[0], f[1], f[2], f[0], f[2], f[3]}) {
                v.push_back(float(((k & 1) ? hi[0] : lo[0]) - eye[0]));
                v.push_back(float(((k & 2) ? hi[1] : lo[1]) - eye[1]));
                v.push_back(float(((k & 4) ? hi[2] : lo[2]) - eye[2]));
            }
        glNamedBufferSubData(buffer_, 0, GLsizeiptr(v.size() * sizeof(float)), v.data());
        glUseProgram(program_);
        glUniformMatrix4fv(glGetUniformLocation(program_, "m"), 1, GL_FALSE, m);
        glBindVertexArray(vao_);
        glDrawArrays(GL_TRIANGLES, 0, 36);
    }

  private:
    GLuint program_ = 0, vao_ = 0, buffer_ = 0;
};

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
    // The application's framebuffer: colour and a depth buffer (24 bits or more).
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
        parameters.schemes = ridge::lodSchemes(); // every scheme, with its default options
        ridge::Renderer renderer(argv[1], parameters);

        // 1. ridge's own camera: it clears and draws (reverse-Z) into the bound framebuffer.
        const ridge::CameraPose camera = renderer.defaultCamera(width, height);
        ridge::FrameSummary frame{};
        for (const std::string& scheme : renderer.schemes()) {
            ridge::DrawParameters draw;
            draw.scheme = scheme;
            frame = renderer.draw(camera, width, height, draw);
            std::printf("%s: %d patches, %llu triangles, ε %.2f px\n", scheme.c_str(),
                        frame.patches, (unsigned long long)frame.triangles, frame.screen_error_px);
        }
        // The default camera frames the whole terrain: terrain pixels have a reverse-Z depth
        // above the cleared 0.
        std::vector<float> z(size_t(width) * height);
        glReadPixels(0, 0, width, height, GL_DEPTH_COMPONENT, GL_FLOAT, z.data());
        size_t terrain_pixels = 0;
        for (float d : z)
            terrain_pixels += d > 0.f;
        std::printf("terrain covers %.1f %% of the picture\n", 100.0 * terrain_pixels / z.size());
        if (frame.patches < 1 || terrain_pixels < z.size() / 10) {
            std::fprintf(stderr, "ridge_embed_gl: the terrain was not drawn\n");
            return 1;
        }

        // 2. The application's scene. Its highest point, from the archive's own samples.
        const ridge::Terrain terrain(argv[1]);
        const ridge::TerrainInfo& info = terrain.info();
        std::vector<std::array<double, 2>> centres;
        for (int64_t r = 0; r < info.height; ++r)
            for (int64_t c = 0; c < info.width; ++c)
                centres.push_back({c + 0.5, r + 0.5});
        ridge::QueryParameters q;
        q.coordinates = ridge::Coordinates::Pixel;
        q.resampling = ridge::Resampling::Nearest;
        const std::vector<ridge::PointHeight> heights = terrain.heights(centres, q);
        size_t top = 0;
        for (size_t k = 0; k < heights.size(); ++k)
            if (heights[k].status == ridge::HeightStatus::Ok &&
                heights[k].height > heights[top].height)
                top = k;
        const ridge::LocalPoint summit = terrain.localFromPixel(centres[top][0], centres[top][1]);
        const Vec3 peak{summit.x, summit.y, heights[top].height};
        // Its camera: 4 km from the summit, 45° down, GL's default conventions (depth −1..1,
        // GL_LESS, cleared to 1), near 10 m, far 200 km.
        const Vec3 eye{peak[0] - 1697.0, peak[1] - 2263.0, peak[2] + 2828.0};
        const Mat4 view = lookAt(eye, peak);
        const Mat4 proj = perspective(40.0, double(width) / height, 10.0, 2e5);
        glClearColor(0.f, 0.f, 0.f, 1.f);
        glClearDepth(1.0);
        glEnable(GL_DEPTH_TEST);
        glDepthFunc(GL_LESS);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        // Its own object first: a pole through the summit, 1.5 km above and below it.
        const Box pole;
        pole.draw(view, proj, {peak[0] - 25, peak[1] - 25, peak[2] - 1500},
                  {peak[0] + 25, peak[1] + 25, peak[2] + 1500});
        // Then the terrain, with the same matrices and conventions, over the scene.
        ridge::HostView host;
        host.view = view;
        host.projection = proj;
        host.width = width;
        host.height = height;
        host.depth = ridge::DepthConvention::Standard;
        ridge::DrawParameters over;
        over.clear = false;
        over.sky = false;
        renderer.draw(host, over);
        // ridge left the application's state as it was: its depth test and function still hold.
        GLint depth_func = 0;
        glGetIntegerv(GL_DEPTH_FUNC, &depth_func);
        if (depth_func != GL_LESS || !glIsEnabled(GL_DEPTH_TEST)) {
            std::fprintf(stderr, "ridge_embed_gl: the application's GL state changed\n");
            return 1;
        }
        // The pole shows above the summit's pixel and the mountain hides it below.
        double gx = 0, gy = 0, tx = 0, ty = 0;
        project(view, proj, width, height, peak, gx, gy);
        project(view, proj, width, height, {peak[0], peak[1], peak[2] + 1500}, tx, ty);
        std::vector<unsigned char> rgba(size_t(width) * height * 4);
        glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
        auto magenta = [&](int x, int y) { // y down from the top
            const unsigned char* p = &rgba[(size_t(height - 1 - y) * width + size_t(x)) * 4];
            return p[0] > 250 && p[1] < 5 && p[2] > 250;
        };
        int above = 0, below = 0, rows_above = 0, rows_below = 0;
        for (int y = int(ty) + 2; y <= int(gy) - 5; ++y, ++rows_above)
            above += magenta(int(gx), y);
        for (int y = int(gy) + 5; y < std::min(height, int(gy) + 40); ++y, ++rows_below)
            below += magenta(int(gx), y);
        std::printf("pole: visible on %d of %d rows above the summit, %d of %d below it\n", above,
                    rows_above, below, rows_below);
        if (above != rows_above || below != 0 || rows_above < 20) {
            std::fprintf(stderr, "ridge_embed_gl: the pole and the terrain do not intersect\n");
            return 1;
        }

        // 3. What is under the summit's pixel: a point of the drawn terrain, with lon/lat.
        const std::optional<ridge::TerrainHit> hit = renderer.pick(gx, gy);
        if (!hit || !hit->lon_lat) {
            std::fprintf(stderr, "ridge_embed_gl: the pick missed the summit\n");
            return 1;
        }
        std::printf("pick at pixel (%.1f, %.1f): %.5f E, %.5f N, %.1f m (level %d, within %.2f m "
                    "of the source); the highest sample: %.1f m\n",
                    gx, gy, (*hit->lon_lat)[0], (*hit->lon_lat)[1], hit->height, hit->level,
                    hit->error_bound, peak[2]);
    } catch (const ridge::Error& e) {
        std::fprintf(stderr, "ridge_embed_gl: %s\n", e.what());
        return 1;
    }
    return 0;
}
