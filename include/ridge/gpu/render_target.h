#pragma once
// An off-screen framebuffer: GL_RGBA8 colour + GL_DEPTH_COMPONENT32F depth, optionally
// multisampled. The way to render in a HeadlessContext, which has no default framebuffer.
#include "ridge/gpu/gl_objects.h"

#include <cstdint>
#include <vector>

namespace ridge::gpu {

// Needs a current GL context for its whole life (see context.h); move-only.
class RenderTarget {
  public:
    // `width` x `height` pixels; `samples` > 1 renders into multisampled renderbuffers that are
    // resolved (blitted) into single-sample textures for readback. Throws ridge::Error for a
    // non-positive size, a size or sample count over the driver's limits, or an incomplete FBO.
    RenderTarget(int width, int height, int samples = 1);

    // Binds framebuffer() to GL_FRAMEBUFFER and sets the viewport to the whole target.
    void bind() const;
    // Colour as RGBA8, width*height*4 bytes, TOP row first (GL's origin is bottom-left; this
    // flips it to image order). Resolves first when multisampled. Stalls until rendering ends.
    std::vector<uint8_t> readRgba() const;
    // Window-space depth in [0, 1], width*height floats, top row first. With samples > 1 each
    // pixel holds one of its samples' depths (blit resolves depth by picking a sample).
    std::vector<float> readDepth() const;

    int width() const { return width_; }
    int height() const { return height_; }
    int samples() const { return samples_; }
    // The framebuffer to draw into (the multisampled one when samples > 1).
    GLuint framebuffer() const;

  private:
    void resolve(GLbitfield mask) const; // multisampled -> single-sample, no-op when samples 1

    int width_;
    int height_;
    int samples_;
    GlFramebuffer resolved_fbo_; // single-sample; the draw target too when samples == 1
    GlTexture colour_{GL_TEXTURE_2D};
    GlTexture depth_{GL_TEXTURE_2D};
    GlFramebuffer msaa_fbo_; // only attached when samples > 1
    GlRenderbuffer msaa_colour_;
    GlRenderbuffer msaa_depth_;
};

} // namespace ridge::gpu
