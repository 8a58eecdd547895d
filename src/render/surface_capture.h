#pragma once
// Transform-feedback capture of a frame's triangles (internal to ridge_render), for
// TerrainRenderer::capture and lastFrameSurface: the rasterizer discarded, a scheme's capture
// programs write every triangle they produce into one buffer, sized for the worst case.
#include "patch_instances.h"

#include "ridge/gpu/gl_objects.h"
#include "ridge/gpu/render_target.h"
#include "ridge/gpu/shader_program.h"
#include "ridge/render/terrain_renderer.h"

#include <cstddef>
#include <functional>
#include <memory>

namespace ridge::render {

class TerrainScheme;
struct SchemeFrame;

class SurfaceCapture {
  public:
    // The triangles `scheme` draws for frame.instances (already in the instance buffer) as
    // `frame`; `set_uniforms` sets the frame's uniforms of each capture program. Throws
    // ridge::Error when the feedback buffer kept fewer triangles than were generated.
    CapturedSurface capture(TerrainScheme& scheme, const SchemeFrame& frame,
                            const std::function<void(const gpu::ShaderProgram&)>& set_uniforms);
    // The same triangles left on the GPU: returns how many vertices feedback() now holds
    // (CapturedVertex each, 3 per triangle), valid until the next capture or record.
    size_t record(TerrainScheme& scheme, const SchemeFrame& frame,
                  const std::function<void(const gpu::ShaderProgram&)>& set_uniforms);
    const gpu::GlBuffer& feedback() const { return feedback_; }

  private:
    static constexpr size_t kFirstBytes = size_t{4} << 20;
    // Gives the feedback buffer at least `bytes` (its contents are not kept).
    void reserve(size_t bytes);

    gpu::GlBuffer feedback_;
    size_t capacity_ = 0; // bytes
    size_t needed_ = 0;   // bytes the last capture generated
    gpu::GlQuery generated_{GL_PRIMITIVES_GENERATED};
    gpu::GlQuery written_{GL_TRANSFORM_FEEDBACK_PRIMITIVES_WRITTEN};
    // Drawing needs a complete framebuffer even with the rasterizer discarded; a surfaceless
    // context has none, so capture binds this one.
    std::unique_ptr<gpu::RenderTarget> target_;
};

} // namespace ridge::render
