#include "sky.h"

#include "frame_uniforms.h"

#include <glm/gtc/matrix_inverse.hpp>

#include <algorithm>

namespace ridge::render {

Sky::Sky() : program_({{GL_VERTEX_SHADER, "sky.vert"}, {GL_FRAGMENT_SHADER, "sky.frag"}}) {}

void Sky::draw(const glm::dmat4& view_projection, glm::dvec3 up, double altitude) const
{
    // Background only: no depth written, the cleared depth stays the far value.
    glDisable(GL_DEPTH_TEST);
    glDepthMask(GL_FALSE);
    program_.use();
    setMatrix(program_, "u_inverse_view_projection", glm::inverse(view_projection));
    glUniform3f(program_.uniform("u_horizon_colour"), kHorizonColour.r, kHorizonColour.g,
                kHorizonColour.b);
    glUniform3f(program_.uniform("u_zenith_colour"), kZenithColour.r, kZenithColour.g,
                kZenithColour.b);
    glUniform3f(program_.uniform("u_up"), float(up.x), float(up.y), float(up.z));
    const double space = std::clamp((altitude - 2e4) / 1e5, 0.0, 1.0);
    glUniform1f(program_.uniform("u_space"), float(space * space * (3.0 - 2.0 * space)));
    glBindVertexArray(empty_vao_.id());
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glDepthMask(GL_TRUE);
}

} // namespace ridge::render
