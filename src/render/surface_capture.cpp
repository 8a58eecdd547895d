#include "surface_capture.h"

#include "instance_buffer.h"
#include "terrain_scheme.h"

#include "ridge/core/error.h"

#include <string>

namespace ridge::render {

static_assert(sizeof(CapturedVertex) == 20, "must match the interleaved feedback varyings");

CapturedSurface
SurfaceCapture::capture(TerrainScheme& scheme, const SchemeFrame& frame,
                        const std::function<void(const gpu::ShaderProgram&)>& set_uniforms)
{
    const PatchInstances& ranges = frame.instances;
    CapturedSurface out;
    out.camera_position = frame.camera.position();
    out.patches = ranges.patches;
    for (const GpuPatchInstance& r : ranges.records)
        out.skirt_depth.push_back(r.skirt_depth);
    if (ranges.total() == 0)
        return out;

    scheme.beginDraw(frame);
    for (const gpu::ShaderProgram* p : scheme.programs(true, frame.settings))
        set_uniforms(*p);
    GLint previous_framebuffer = 0;
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &previous_framebuffer);
    if (!target_)
        target_ = std::make_unique<gpu::RenderTarget>(1, 1, 1);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, target_->framebuffer());
    glEnable(GL_RASTERIZER_DISCARD);
    // Clipping makes at most 3 triangles and 2 walls (4 triangles) of one.
    const size_t per_instance = scheme.maxTrianglesPerInstance(frame.settings.skirts);
    const size_t bytes =
        (ranges.whole + 7 * ranges.partial) * per_instance * 3 * sizeof(CapturedVertex);
    if (bytes > capacity_) {
        feedback_ = gpu::GlBuffer();
        glNamedBufferStorage(feedback_.id(), bytes, nullptr, 0);
        capacity_ = bytes;
    }
    // One feedback session per program (programs cannot change while it is active); the
    // second appends after the first.
    size_t stored_total = 0;
    forEachGroup(scheme.programs(true, frame.settings), ranges,
                 [&](const gpu::ShaderProgram& p, size_t first, size_t n) {
                     p.use();
                     const GLintptr offset = GLintptr(stored_total * 3 * sizeof(CapturedVertex));
                     glBindBufferRange(GL_TRANSFORM_FEEDBACK_BUFFER, 0, feedback_.id(), offset,
                                       GLsizeiptr(capacity_ - size_t(offset)));
                     glBeginQuery(GL_TRANSFORM_FEEDBACK_PRIMITIVES_WRITTEN, written_.id());
                     glBeginQuery(GL_PRIMITIVES_GENERATED, generated_.id());
                     glBeginTransformFeedback(GL_TRIANGLES);
                     scheme.draw(p, frame, first, n);
                     glEndTransformFeedback();
                     glEndQuery(GL_PRIMITIVES_GENERATED);
                     glEndQuery(GL_TRANSFORM_FEEDBACK_PRIMITIVES_WRITTEN);
                     GLuint64 generated = 0, stored = 0;
                     glGetQueryObjectui64v(generated_.id(), GL_QUERY_RESULT, &generated);
                     glGetQueryObjectui64v(written_.id(), GL_QUERY_RESULT, &stored);
                     if (generated != stored)
                         throw Error("terrain renderer: transform feedback kept " +
                                     std::to_string(stored) + " of " + std::to_string(generated) +
                                     " triangles");
                     stored_total += size_t(stored);
                 });
    glDisable(GL_RASTERIZER_DISCARD);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, GLuint(previous_framebuffer));
    out.vertices.resize(stored_total * 3);
    glGetNamedBufferSubData(feedback_.id(), 0, out.vertices.size() * sizeof(CapturedVertex),
                            out.vertices.data());
    gpu::checkGlError("terrain renderer: capture");
    return out;
}

} // namespace ridge::render
