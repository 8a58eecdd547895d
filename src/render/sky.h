#pragma once
// The background of a frame that clears (internal to ridge_render): a gradient from the
// horizon's colour to the zenith's (shaders/sky.*), drawn behind everything. The terrain's fog
// fades to the horizon's colour (frame_uniforms.cpp).
#include "ridge/gpu/gl_objects.h"
#include "ridge/gpu/shader_program.h"

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

namespace ridge::render {

inline const glm::vec3 kHorizonColour(0.78f, 0.84f, 0.90f);
inline const glm::vec3 kZenithColour(0.30f, 0.48f, 0.75f);

class Sky {
  public:
    Sky(); // needs a current GL context, as long as it lives

    // Draws the sky for `view_projection` (camera-relative terrain frame → clip) with depth
    // testing off and no depth written (the cleared depth stays the far value); leaves depth
    // writes on and the depth test off.
    void draw(const glm::dmat4& view_projection) const;

  private:
    gpu::ShaderProgram program_;
    gpu::GlVertexArray empty_vao_;
};

} // namespace ridge::render
