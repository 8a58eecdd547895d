#include "ridge/gpu/scoped_raster_state.h"

namespace ridge::gpu {

ScopedRasterState::ScopedRasterState()
{
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &framebuffer_);
    glGetIntegerv(GL_VIEWPORT, viewport_);
    glGetIntegerv(GL_SCISSOR_BOX, scissor_);
    glGetIntegerv(GL_BLEND_EQUATION_RGB, &equation_rgb_);
    glGetIntegerv(GL_BLEND_EQUATION_ALPHA, &equation_alpha_);
    glGetIntegerv(GL_POLYGON_MODE, polygon_mode_);
    for (size_t k = 0; k < kSwitches.size(); ++k)
        enabled_[k] = glIsEnabled(kSwitches[k]);
}

ScopedRasterState::~ScopedRasterState()
{
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, GLuint(framebuffer_));
    glViewport(viewport_[0], viewport_[1], viewport_[2], viewport_[3]);
    glScissor(scissor_[0], scissor_[1], scissor_[2], scissor_[3]);
    glBlendEquationSeparate(GLenum(equation_rgb_), GLenum(equation_alpha_));
    // Core profiles take one mode for both faces; GL_POLYGON_MODE reports it twice.
    glPolygonMode(GL_FRONT_AND_BACK, GLenum(polygon_mode_[0]));
    for (size_t k = 0; k < kSwitches.size(); ++k)
        (enabled_[k] ? glEnable : glDisable)(kSwitches[k]);
}

} // namespace ridge::gpu
