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

  private:
    gpu::GlBuffer feedback_;
    size_t capacity_ = 0; // bytes
    gpu::GlQuery generated_{GL_PRIMITIVES_GENERATED};
    gpu::GlQuery written_{GL_TRANSFORM_FEEDBACK_PRIMITIVES_WRITTEN};
    // Drawing needs a complete framebuffer even with the rasterizer discarded; a surfaceless
    // context has none, so capture binds this one.
    std::unique_ptr<gpu::RenderTarget> target_;
};

} // namespace ridge::render
