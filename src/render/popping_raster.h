#pragma once
// The popping metric on the GPU (internal to ridge_render; TerrainRenderer::measureFramePopping):
// render::measurePopping's figure without bringing a surface to the CPU. Each frame's captured
// surface (SurfaceCapture::record) is drawn top-down into a height texture over the window of
// finest samples its vertices span (a compute pass finds it), one texel per sample (or per
// `stride` samples when the window exceeds kMaxTexels), and a compute pass projects the
// previous frame's and this frame's height of every sample both windows hold through the
// camera and reduces the largest displacement. Two targets take turns: this frame's surface is
// the next frame's previous one. Plane frames only: on the ellipsoid a sample's position is
// not linear in the drawn vertices (the CPU measure stays there).
#include "ridge/gpu/gl_objects.h"
#include "ridge/gpu/shader_program.h"
#include "ridge/lod/camera.h"
#include "ridge/lod/terrain_frame.h"
#include "ridge/render/frame_measures.h"

#include <array>
#include <cstddef>

namespace ridge::render {

class PoppingRaster {
  public:
    // At most this many texels per height texture (128 MiB as R32F): a larger window is
    // sampled every `stride` samples.
    static constexpr long long kMaxTexels = 32LL << 20;

    // For surfaces over `frame` (a plane frame; throws ridge::Error on the ellipsoid).
    explicit PoppingRaster(const lod::TerrainFrame& frame);

    // Draws this frame's surface (the feedback buffer's first `vertices` CapturedVertex,
    // camera-relative to camera.position()) and compares it with the previous call's, seen from
    // `camera`. The first call after construction or reset() returns an empty report.
    PoppingReport next(const gpu::GlBuffer& feedback, size_t vertices, const lod::Camera& camera);
    void reset() { have_previous_ = false; }

  private:
    struct Window {
        int x0 = 0, y0 = 0;        // first sample (column, row), multiples of the stride
        int stride = 1;            // samples per texel
        int width = 0, height = 0; // texels; 0: the surface covers no sample
    };
    struct Target { // one surface's heights
        Window window;
        int allocated_width = 0, allocated_height = 0;
        gpu::GlTexture heights{GL_TEXTURE_2D};
        gpu::GlFramebuffer framebuffer;
    };
    Window windowOf(const gpu::GlBuffer& feedback, size_t vertices, glm::dvec3 camera);
    void draw(Target& target, const gpu::GlBuffer& feedback, size_t vertices, glm::dvec3 camera);
    PoppingReport reduce(const Target& before, const Target& after, const lod::Camera& camera);

    const lod::TerrainFrame& frame_;
    gpu::ShaderProgram window_program_, heights_program_, reduce_program_;
    gpu::GlBuffer window_buffer_, result_buffer_;
    gpu::GlVertexArray vertex_array_;
    std::array<Target, 2> targets_;
    int current_ = 0; // the target the next surface goes to
    bool have_previous_ = false;
};

} // namespace ridge::render
