#include "surface_capture.h"

#include "instance_buffer.h"
#include "terrain_scheme.h"

#include "ridge/core/error.h"
#include "ridge/gpu/scoped_raster_state.h"

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
    out.vertices.resize(record(scheme, frame, set_uniforms));
    if (out.vertices.empty())
        return out;
    glGetNamedBufferSubData(feedback_.id(), 0, out.vertices.size() * sizeof(CapturedVertex),
                            out.vertices.data());
    gpu::checkGlError("terrain renderer: capture");
    return out;
}

size_t SurfaceCapture::record(TerrainScheme& scheme, const SchemeFrame& frame,
                              const std::function<void(const gpu::ShaderProgram&)>& set_uniforms)
{
    const PatchInstances& ranges = frame.instances;
    if (ranges.total() == 0)
        return 0;

    scheme.beginDraw(frame);
    forEachGroup(scheme, true, frame.settings, ranges,
                 [&](const gpu::ShaderProgram& p, size_t, size_t) { set_uniforms(p); });
    if (!target_)
        target_ = std::make_unique<gpu::RenderTarget>(1, 1, 1);
    // The rasterizer discarded and the 1×1 target bound until the capture ends, thrown or not.
    const gpu::ScopedRasterState saved;
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, target_->framebuffer());
    glEnable(GL_RASTERIZER_DISCARD);
    // The worst case: every instance at its most triangles, and clipping makes at most 3
    // triangles and 2 walls (4 triangles) of one. A frame makes far fewer (a 1080p fly-over
    // over the Sierra: 50 MB of a worst case past what llvmpipe allocates), so the buffer
    // starts at what the last capture needed and grows when a frame generates more: the
    // capture is then run again, at most a few times (the size at least doubles each time).
    constexpr size_t kVertexBytes = 3 * sizeof(CapturedVertex); // a triangle
    const size_t worst = (ranges.whole + 7 * ranges.partial) *
                         scheme.maxTrianglesPerInstance(frame.settings.skirts) * kVertexBytes;
    size_t wanted = std::min(worst, std::max<size_t>(kFirstBytes, needed_ + needed_ / 4));
    size_t stored_total = 0;
    for (;;) {
        reserve(wanted);
        // One feedback session per program (programs cannot change while it is active); the
        // next appends after the previous. A group that does not fit is still counted.
        size_t generated_total = 0;
        stored_total = 0;
        forEachGroup(scheme, true, frame.settings, ranges,
                     [&](const gpu::ShaderProgram& p, size_t first, size_t n) {
                         p.use();
                         const size_t offset = stored_total * kVertexBytes;
                         const bool room = offset < capacity_;
                         if (room)
                             glBindBufferRange(GL_TRANSFORM_FEEDBACK_BUFFER, 0, feedback_.id(),
                                               GLintptr(offset), GLsizeiptr(capacity_ - offset));
                         glBeginQuery(GL_TRANSFORM_FEEDBACK_PRIMITIVES_WRITTEN, written_.id());
                         glBeginQuery(GL_PRIMITIVES_GENERATED, generated_.id());
                         if (room)
                             glBeginTransformFeedback(GL_TRIANGLES);
                         scheme.draw(p, frame, first, n);
                         if (room)
                             glEndTransformFeedback();
                         glEndQuery(GL_PRIMITIVES_GENERATED);
                         glEndQuery(GL_TRANSFORM_FEEDBACK_PRIMITIVES_WRITTEN);
                         GLuint64 generated = 0, stored = 0;
                         glGetQueryObjectui64v(generated_.id(), GL_QUERY_RESULT, &generated);
                         glGetQueryObjectui64v(written_.id(), GL_QUERY_RESULT, &stored);
                         generated_total += size_t(generated);
                         stored_total += room ? size_t(stored) : 0;
                     });
        needed_ = generated_total * kVertexBytes;
        if (stored_total == generated_total)
            break;
        if (capacity_ >= worst || needed_ > worst)
            throw Error("terrain renderer: transform feedback kept " +
                        std::to_string(stored_total) + " of " + std::to_string(generated_total) +
                        " triangles");
        wanted = std::min(worst, std::max(2 * capacity_, needed_ + needed_ / 4));
    }
    gpu::checkGlError("terrain renderer: capture");
    return stored_total * 3;
}

void SurfaceCapture::reserve(size_t bytes)
{
    if (bytes <= capacity_)
        return;
    bytes = (bytes + 4095) & ~size_t{4095}; // binding ranges are multiples of 4 bytes
    gpu::checkGlError("terrain renderer: before the capture buffer");
    feedback_ = gpu::GlBuffer();
    capacity_ = 0;
    glNamedBufferStorage(feedback_.id(), GLsizeiptr(bytes), nullptr, 0);
    if (glGetError() == GL_OUT_OF_MEMORY)
        throw Error("terrain renderer: the GL implementation cannot allocate a " +
                    std::to_string(bytes >> 20) + " MiB transform feedback buffer for the capture");
    capacity_ = bytes;
}

} // namespace ridge::render
