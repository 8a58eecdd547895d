#include "popping_raster.h"

#include "ridge/core/error.h"
#include "ridge/gpu/scoped_raster_state.h"
#include "ridge/render/terrain_renderer.h"

#include <algorithm>
#include <bit>
#include <cfloat>
#include <climits>
#include <cstdint>

namespace ridge::render {

namespace {

constexpr GLuint kVertexBinding = 0;

void setVec2(const gpu::ShaderProgram& p, const char* name, double x, double y)
{
    glUniform2f(p.uniform(name), float(x), float(y));
}

int ceilDiv(int a, int b)
{
    return (a + b - 1) / b;
}

} // namespace

PoppingRaster::PoppingRaster(const lod::TerrainFrame& frame)
    : frame_(frame), window_program_({{GL_COMPUTE_SHADER, "popping_window.comp"}}),
      heights_program_({{GL_VERTEX_SHADER, "popping_heights.vert"},
                        {GL_GEOMETRY_SHADER, "popping_heights.geom"},
                        {GL_FRAGMENT_SHADER, "popping_heights.frag"}}),
      reduce_program_({{GL_COMPUTE_SHADER, "popping_reduce.comp"}})
{
    if (frame.onEllipsoid())
        throw Error("popping raster: plane frames only (the CPU measure covers the ellipsoid)");
    glNamedBufferStorage(window_buffer_.id(), 4 * sizeof(GLint), nullptr, GL_DYNAMIC_STORAGE_BIT);
    glNamedBufferStorage(result_buffer_.id(), 3 * sizeof(GLuint), nullptr, GL_DYNAMIC_STORAGE_BIT);
    // CapturedVertex: position at 0, the skirt flag at 16 (the instance at 12 is not read).
    const GLuint vao = vertex_array_.id();
    glEnableVertexArrayAttrib(vao, 0);
    glVertexArrayAttribFormat(vao, 0, 3, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribBinding(vao, 0, kVertexBinding);
    glEnableVertexArrayAttrib(vao, 1);
    glVertexArrayAttribIFormat(vao, 1, 1, GL_INT, GLuint(offsetof(CapturedVertex, skirt)));
    glVertexArrayAttribBinding(vao, 1, kVertexBinding);
    gpu::checkGlError("popping raster: setup");
}

PoppingReport PoppingRaster::next(const gpu::GlBuffer& feedback, size_t vertices,
                                  const lod::Camera& camera)
{
    if (vertices > size_t(INT32_MAX))
        throw Error("popping raster: more vertices than one draw takes");
    Target& now = targets_[size_t(current_)];
    now.window = windowOf(feedback, vertices, camera.position());
    if (now.window.width > 0)
        draw(now, feedback, vertices, camera.position());
    PoppingReport report;
    report.sample_stride = now.window.stride;
    const Target& before = targets_[size_t(1 - current_)];
    if (have_previous_ && now.window.width > 0 && before.window.width > 0)
        report = reduce(before, now, camera);
    have_previous_ = true;
    current_ = 1 - current_;
    return report;
}

PoppingRaster::Window PoppingRaster::windowOf(const gpu::GlBuffer& feedback, size_t vertices,
                                              glm::dvec3 camera)
{
    if (vertices == 0)
        return {};
    const GLint start[4] = {INT_MAX, INT_MAX, INT_MIN, INT_MIN};
    glNamedBufferSubData(window_buffer_.id(), 0, sizeof(start), start);
    window_program_.use();
    glUniform1ui(window_program_.uniform("u_count"), GLuint(vertices));
    setVec2(window_program_, "u_camera_sample", frame_.columnOf(camera.x), frame_.rowOf(camera.y));
    setVec2(window_program_, "u_per_metre", 1.0 / frame_.spacingX(), -1.0 / frame_.spacingY());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, feedback.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, window_buffer_.id());
    glDispatchCompute(GLuint(std::min<size_t>(65535, (vertices + 255) / 256)), 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    // The next capture writes the feedback buffer: still bound here, transform feedback would
    // keep nothing (Mesa).
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, 0);
    GLint span[4] = {};
    glGetNamedBufferSubData(window_buffer_.id(), 0, sizeof(span), span);
    gpu::checkGlError("popping raster: window");

    const PyramidGeometry& g = frame_.geometry();
    const int x1 = std::min(g.width() - 1, span[2]), y1 = std::min(g.height() - 1, span[3]);
    GLint max_size = 0, max_width = 0, max_height = 0;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max_size);
    glGetIntegerv(GL_MAX_FRAMEBUFFER_WIDTH, &max_width);
    glGetIntegerv(GL_MAX_FRAMEBUFFER_HEIGHT, &max_height);
    for (Window w;; ++w.stride) {
        // First samples on the stride's lattice, so that two windows of one stride share it.
        w.x0 = std::max(0, span[0]) / w.stride * w.stride;
        w.y0 = std::max(0, span[1]) / w.stride * w.stride;
        if (x1 < w.x0 || y1 < w.y0)
            return {};
        w.width = (x1 - w.x0) / w.stride + 1;
        w.height = (y1 - w.y0) / w.stride + 1;
        if ((long long)w.width * w.height <= kMaxTexels &&
            w.width <= std::min(max_size, max_width) && w.height <= std::min(max_size, max_height))
            return w;
    }
}

void PoppingRaster::draw(Target& target, const gpu::GlBuffer& feedback, size_t vertices,
                         glm::dvec3 camera)
{
    const Window& w = target.window;
    if (w.width > target.allocated_width || w.height > target.allocated_height) {
        target.allocated_width = std::max(w.width, target.allocated_width);
        target.allocated_height = std::max(w.height, target.allocated_height);
        target.heights = gpu::GlTexture(GL_TEXTURE_2D);
        glTextureStorage2D(target.heights.id(), 1, GL_R32F, target.allocated_width,
                           target.allocated_height);
        glTextureParameteri(target.heights.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTextureParameteri(target.heights.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        target.framebuffer = gpu::GlFramebuffer();
        glNamedFramebufferTexture(target.framebuffer.id(), GL_COLOR_ATTACHMENT0,
                                  target.heights.id(), 0);
        if (glGetError() == GL_OUT_OF_MEMORY ||
            glCheckNamedFramebufferStatus(target.framebuffer.id(), GL_DRAW_FRAMEBUFFER) !=
                GL_FRAMEBUFFER_COMPLETE)
            throw Error("popping raster: the GL implementation cannot draw into a " +
                        std::to_string(target.allocated_width) + "x" +
                        std::to_string(target.allocated_height) + " R32F texture");
    }
    // Put back when the pass ends: the renderer's caller may be drawing its own scene.
    const gpu::ScopedRasterState saved;
    const GLuint framebuffer = target.framebuffer.id();
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, framebuffer);
    glViewport(0, 0, w.width, w.height);
    const GLfloat none[4] = {-FLT_MAX, 0.f, 0.f, 0.f};
    glEnable(GL_SCISSOR_TEST); // the clear: the window, not the whole allocation
    glScissor(0, 0, w.width, w.height);
    glClearBufferfv(GL_COLOR, 0, none);
    for (GLenum cap : {GL_DEPTH_TEST, GL_CULL_FACE, GL_SCISSOR_TEST, GL_RASTERIZER_DISCARD})
        glDisable(cap);
    glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    glEnable(GL_BLEND);
    glBlendEquation(GL_MAX); // the upper surface where seams cover a sample twice

    const gpu::ShaderProgram& p = heights_program_;
    p.use();
    setVec2(p, "u_camera_sample", frame_.columnOf(camera.x), frame_.rowOf(camera.y));
    setVec2(p, "u_window_first", w.x0, w.y0);
    setVec2(p, "u_per_metre", 1.0 / frame_.spacingX(), -1.0 / frame_.spacingY());
    glUniform1f(p.uniform("u_stride"), float(w.stride));
    setVec2(p, "u_texels", w.width, w.height);
    glUniform1f(p.uniform("u_camera_z"), float(camera.z));
    glVertexArrayVertexBuffer(vertex_array_.id(), kVertexBinding, feedback.id(), 0,
                              sizeof(CapturedVertex));
    glBindVertexArray(vertex_array_.id());
    // Grown by 1/32 texel (popping_heights.geom): every sample of a closed triangle is a
    // candidate; the fragment stage decides.
    glUniform1f(p.uniform("u_grow"), 1.f / 32.f);
    glDrawArrays(GL_TRIANGLES, 0, GLsizei(vertices));
    glBindVertexArray(0);
    glVertexArrayVertexBuffer(vertex_array_.id(), kVertexBinding, 0, 0, sizeof(CapturedVertex));
    gpu::checkGlError("popping raster: heights");
}

PoppingReport PoppingRaster::reduce(const Target& before, const Target& after,
                                    const lod::Camera& camera)
{
    const glm::dvec3 c = camera.position();
    const Window& w = after.window;
    const Window& b = before.window;
    const GLuint zero[3] = {0, 0, 0};
    glNamedBufferSubData(result_buffer_.id(), 0, sizeof(zero), zero);
    const gpu::ShaderProgram& p = reduce_program_;
    p.use();
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
    glBindTextureUnit(0, before.heights.id());
    glBindTextureUnit(1, after.heights.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, result_buffer_.id());
    glUniform2i(p.uniform("u_texels"), w.width, w.height);
    glUniform2i(p.uniform("u_first"), w.x0, w.y0);
    glUniform1i(p.uniform("u_stride"), w.stride);
    glUniform2i(p.uniform("u_before_texels"), b.width, b.height);
    glUniform2i(p.uniform("u_before_first"), b.x0, b.y0);
    glUniform1i(p.uniform("u_before_stride"), b.stride);
    setVec2(p, "u_origin", frame_.xOf(w.x0) - c.x, frame_.yOf(w.y0) - c.y);
    setVec2(p, "u_texel_metres", w.stride * frame_.spacingX(), -w.stride * frame_.spacingY());
    glUniform1f(p.uniform("u_camera_z"), float(c.z));
    const glm::mat4 vp(camera.viewProjection());
    glUniformMatrix4fv(p.uniform("u_view_projection"), 1, GL_FALSE, &vp[0][0]);
    const glm::vec3 forward(camera.forward());
    glUniform3f(p.uniform("u_forward"), forward.x, forward.y, forward.z);
    glUniform1f(p.uniform("u_near"), float(camera.nearPlane()));
    setVec2(p, "u_viewport", camera.viewport().width, camera.viewport().height);
    glDispatchCompute(GLuint(ceilDiv(w.width, 8)), GLuint(ceilDiv(w.height, 8)), 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    GLuint result[3] = {};
    glGetNamedBufferSubData(result_buffer_.id(), 0, sizeof(result), result);
    gpu::checkGlError("popping raster: reduce");
    PoppingReport report;
    report.sample_stride = std::max(w.stride, b.stride);
    report.samples = result[0];
    report.max_px = double(std::bit_cast<float>(result[1]));
    report.max_metres = double(std::bit_cast<float>(result[2]));
    return report;
}

} // namespace ridge::render
