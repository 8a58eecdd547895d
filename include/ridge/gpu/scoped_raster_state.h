#pragma once
// The rasterization state one of ridge's own GPU passes changes (a surface capture, the
// popping raster), saved when a ScopedRasterState is made and put back when it dies, thrown
// or not: the draw framebuffer, viewport, scissor box, blend equations, polygon mode and the
// switches below. The renderer's caller may be drawing its own scene around such a pass.
// (render::HostGlState is the host-facing guard: far more state, around a whole draw.)
#include <epoxy/gl.h>

#include <array>

namespace ridge::gpu {

class ScopedRasterState {
  public:
    // Needs a current context.
    ScopedRasterState();
    ~ScopedRasterState();
    ScopedRasterState(const ScopedRasterState&) = delete;
    ScopedRasterState& operator=(const ScopedRasterState&) = delete;

    static constexpr std::array<GLenum, 5> kSwitches = {GL_BLEND, GL_DEPTH_TEST, GL_CULL_FACE,
                                                        GL_SCISSOR_TEST, GL_RASTERIZER_DISCARD};

  private:
    GLint framebuffer_ = 0, viewport_[4] = {}, scissor_[4] = {};
    GLint equation_rgb_ = GL_FUNC_ADD, equation_alpha_ = GL_FUNC_ADD;
    GLint polygon_mode_[2] = {GL_FILL, GL_FILL};
    std::array<GLboolean, kSwitches.size()> enabled_ = {};
};

} // namespace ridge::gpu
