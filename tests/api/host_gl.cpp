#include "host_gl.h"

#include <epoxy/egl.h>
#include <epoxy/gl.h>

#include <cmath>
#include <stdexcept>

namespace host {

bool makeContext()
{
    static const bool made = [] {
        EGLDisplay display = EGL_NO_DISPLAY;
        bool pbuffer = false;
        if (epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_EXT_platform_base") &&
            epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_MESA_platform_surfaceless"))
            display = eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY,
                                               nullptr);
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
    }();
    return made;
}

Mat4 multiply(const Mat4& a, const Mat4& b)
{
    Mat4 out{};
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) {
            double sum = 0.0;
            for (int k = 0; k < 4; ++k)
                sum += a[size_t(k * 4 + r)] * b[size_t(c * 4 + k)];
            out[size_t(c * 4 + r)] = sum;
        }
    return out;
}

namespace {

Vec3 normalize(const Vec3& v)
{
    const double l = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    return {v[0] / l, v[1] / l, v[2] / l};
}

Vec3 cross(const Vec3& a, const Vec3& b)
{
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

double dot(const Vec3& a, const Vec3& b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

} // namespace

Mat4 lookAt(const Vec3& eye, const Vec3& target)
{
    const Vec3 f = normalize({target[0] - eye[0], target[1] - eye[1], target[2] - eye[2]});
    const Vec3 s = normalize(cross(f, {0.0, 0.0, 1.0}));
    const Vec3 u = cross(s, f);
    return {s[0], u[0], -f[0], 0.0, s[1],         u[1],         -f[1],       0.0,
            s[2], u[2], -f[2], 0.0, -dot(s, eye), -dot(u, eye), dot(f, eye), 1.0};
}

Mat4 perspective(double fov_y_degrees, double aspect, double n, double f,
                 ridge::DepthConvention convention)
{
    const double t = 1.0 / std::tan(fov_y_degrees * M_PI / 360.0);
    Mat4 p{};
    p[0] = t / aspect;
    p[5] = t;
    p[11] = -1.0;
    switch (convention) {
    case ridge::DepthConvention::Standard:
        p[10] = -(f + n) / (f - n);
        p[14] = -2.0 * f * n / (f - n);
        break;
    case ridge::DepthConvention::ZeroToOne:
        p[10] = -f / (f - n);
        p[14] = -f * n / (f - n);
        break;
    case ridge::DepthConvention::ReverseZ: // infinite far plane
        p[10] = 0.0;
        p[14] = n;
        break;
    }
    return p;
}

bool project(const Mat4& view, const Mat4& projection, int width, int height, const Vec3& p,
             double& x, double& y)
{
    const Mat4 m = multiply(projection, view);
    double clip[4];
    for (int r = 0; r < 4; ++r)
        clip[r] = m[size_t(r)] * p[0] + m[size_t(4 + r)] * p[1] + m[size_t(8 + r)] * p[2] +
                  m[size_t(12 + r)];
    if (clip[3] <= 0.0)
        return false;
    x = (clip[0] / clip[3] * 0.5 + 0.5) * width;
    y = (0.5 - clip[1] / clip[3] * 0.5) * height;
    return true;
}

Framebuffer::Framebuffer(int width, int height) : width_(width), height_(height)
{
    glGenRenderbuffers(1, &colour_);
    glBindRenderbuffer(GL_RENDERBUFFER, colour_);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
    glGenRenderbuffers(1, &depth_);
    glBindRenderbuffer(GL_RENDERBUFFER, depth_);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, width, height);
    glGenFramebuffers(1, &fbo_);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, colour_);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        throw std::runtime_error("host: incomplete framebuffer");
    bind();
}

Framebuffer::~Framebuffer()
{
    glDeleteFramebuffers(1, &fbo_);
    glDeleteRenderbuffers(1, &colour_);
    glDeleteRenderbuffers(1, &depth_);
}

void Framebuffer::bind() const
{
    glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
    glViewport(0, 0, width_, height_);
}

std::vector<uint8_t> Framebuffer::readRgba() const
{
    std::vector<uint8_t> rows(size_t(width_) * height_ * 4), out(rows.size());
    glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo_);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE, rows.data());
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    const size_t row = size_t(width_) * 4;
    for (int y = 0; y < height_; ++y) // GL's rows bottom first
        std::copy_n(rows.data() + size_t(height_ - 1 - y) * row, row, out.data() + size_t(y) * row);
    return out;
}

void beginHostFrame(ridge::DepthConvention convention, const std::array<float, 4>& rgba)
{
    const bool reverse = convention == ridge::DepthConvention::ReverseZ;
    glClipControl(GL_LOWER_LEFT, convention == ridge::DepthConvention::Standard
                                     ? GL_NEGATIVE_ONE_TO_ONE
                                     : GL_ZERO_TO_ONE);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(reverse ? GL_GREATER : GL_LESS);
    glDepthMask(GL_TRUE);
    glClearColor(rgba[0], rgba[1], rgba[2], rgba[3]);
    glClearDepth(reverse ? 0.0 : 1.0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
}

namespace {

unsigned compile(GLenum kind, const char* source)
{
    const GLuint shader = glCreateShader(kind);
    glShaderSource(shader, 1, &source, nullptr);
    glCompileShader(shader);
    GLint ok = 0;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok)
        throw std::runtime_error("host: shader does not compile");
    return shader;
}

} // namespace

Box::Box()
{
    // Positions relative to the eye in double on the CPU, floats on the GPU (as ridge does):
    // the host's matrices are applied to box corners made camera-relative per draw.
    const char* vs = "#version 450 core\n"
                     "layout(location = 0) in vec3 position;\n"
                     "uniform mat4 u_view_projection;\n"
                     "void main() { gl_Position = u_view_projection * vec4(position, 1.0); }\n";
    const char* fs = "#version 450 core\n"
                     "uniform vec3 u_colour;\n"
                     "out vec4 colour;\n"
                     "void main() { colour = vec4(u_colour, 1.0); }\n";
    program_ = glCreateProgram();
    const unsigned v = compile(GL_VERTEX_SHADER, vs), f = compile(GL_FRAGMENT_SHADER, fs);
    glAttachShader(program_, v);
    glAttachShader(program_, f);
    glLinkProgram(program_);
    glDeleteShader(v);
    glDeleteShader(f);
    GLint ok = 0;
    glGetProgramiv(program_, GL_LINK_STATUS, &ok);
    if (!ok)
        throw std::runtime_error("host: program does not link");
    glCreateVertexArrays(1, &vao_);
    glCreateBuffers(1, &buffer_);
    glNamedBufferStorage(buffer_, 36 * 3 * sizeof(float), nullptr, GL_DYNAMIC_STORAGE_BIT);
    glVertexArrayVertexBuffer(vao_, 0, buffer_, 0, 3 * sizeof(float));
    glEnableVertexArrayAttrib(vao_, 0);
    glVertexArrayAttribFormat(vao_, 0, 3, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribBinding(vao_, 0, 0);
}

Box::~Box()
{
    glDeleteProgram(program_);
    glDeleteVertexArrays(1, &vao_);
    glDeleteBuffers(1, &buffer_);
}

void Box::draw(const Mat4& view, const Mat4& projection, const Vec3& lo, const Vec3& hi,
               const std::array<float, 3>& rgb) const
{
    // The eye in world coordinates (−Rᵀt), then corners relative to it and the view's
    // rotation alone: float vertices stay small whatever the world coordinates.
    Vec3 eye{};
    for (int i = 0; i < 3; ++i)
        eye[size_t(i)] = -(view[size_t(i * 4)] * view[12] + view[size_t(i * 4 + 1)] * view[13] +
                           view[size_t(i * 4 + 2)] * view[14]);
    Mat4 rotation = view;
    rotation[12] = rotation[13] = rotation[14] = 0.0;
    const Mat4 vp = multiply(projection, rotation);
    float matrix[16];
    for (int i = 0; i < 16; ++i)
        matrix[i] = float(vp[size_t(i)]);
    const Vec3 c[2] = {{lo[0] - eye[0], lo[1] - eye[1], lo[2] - eye[2]},
                       {hi[0] - eye[0], hi[1] - eye[1], hi[2] - eye[2]}};
    auto corner = [&](int k) {
        return std::array<float, 3>{float(c[k & 1][0]), float(c[(k >> 1) & 1][1]),
                                    float(c[(k >> 2) & 1][2])};
    };
    // Six faces, two triangles each (corner bits: x, y, z).
    const int faces[6][4] = {{0, 2, 6, 4}, {1, 3, 7, 5}, {0, 1, 5, 4},
                             {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 5, 7, 6}};
    std::vector<float> vertices;
    for (const auto& f : faces)
        for (int k : {f[0], f[1], f[2], f[0], f[2], f[3]})
            for (float v : corner(k))
                vertices.push_back(v);
    glNamedBufferSubData(buffer_, 0, GLsizeiptr(vertices.size() * sizeof(float)), vertices.data());
    glUseProgram(program_);
    glUniformMatrix4fv(glGetUniformLocation(program_, "u_view_projection"), 1, GL_FALSE, matrix);
    glUniform3f(glGetUniformLocation(program_, "u_colour"), rgb[0], rgb[1], rgb[2]);
    glBindVertexArray(vao_);
    glDrawArrays(GL_TRIANGLES, 0, 36);
}

} // namespace host
