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
// The globe's aerial haze (terrain.frag): extinction at sea level, 1/e over 150 km (a clear
// day's visibility), falling with altitude over the air's scale height.
inline constexpr double kSeaLevelFogPerMetre = 1.0 / 150e3;
inline constexpr double kAirScaleHeightMetres = 8000.0;
inline const glm::vec3 kZenithColour(0.30f, 0.48f, 0.75f);

class Sky {
  public:
    Sky(); // needs a current GL context, as long as it lives

    // Draws the sky for `view_projection` (camera-relative terrain frame → clip) with depth
    // testing off and no depth written (the cleared depth stays the far value); leaves depth
    // writes on and the depth test off. `up`: the local up at the camera (+z on a plane);
    // `altitude`: the camera's height, metres — the sky turns to the black of space between
    // 20 and 120 km (a globe seen from orbit).
    void draw(const glm::dmat4& view_projection, glm::dvec3 up = glm::dvec3(0.0, 0.0, 1.0),
              double altitude = 0.0) const;

  private:
    gpu::ShaderProgram program_;
    gpu::GlVertexArray empty_vao_;
};

} // namespace ridge::render
