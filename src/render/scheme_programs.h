#pragma once
// The four programs every terrain scheme draws with (internal to ridge_render): its own
// surface stages, then either its fragment stage (terrain.frag unless it has its own) or
// transform feedback of
// Capture.tf_* (capture), each with or without terrain_clip.geom for patches that reach past
// the valid extent. Compiled on first use, so a renderer that never draws a scheme never
// compiles it.
#include "ridge/gpu/shader_program.h"

#include <array>
#include <string>
#include <vector>

namespace ridge::render {

class SchemePrograms {
  public:
    // `surface`: the stages up to the tessellator or vertex shader, e.g. {terrain.vert,
    // terrain.tesc, terrain.tese}; every one must write the Vertex and Capture blocks that
    // terrain_clip.geom and the fragment stage read. `fragment`: the fragment shader's file
    // (a scheme whose surface is not drawn from patch layers brings its own).
    explicit SchemePrograms(std::vector<gpu::ShaderStage> surface,
                            std::string fragment = "terrain.frag")
        : surface_(std::move(surface)), fragment_(std::move(fragment))
    {
    }

    // {whole patches, clipped patches} for drawing or for capture.
    std::array<const gpu::ShaderProgram*, 2> get(bool capture);

  private:
    std::vector<gpu::ShaderStage> surface_;
    std::string fragment_;
    bool compiled_[2] = {false, false};
    gpu::ShaderProgram programs_[2][2]; // [capture][clip]
};

} // namespace ridge::render
