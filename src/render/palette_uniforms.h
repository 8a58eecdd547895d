#pragma once
// Sends ridge/core/terrain_palette.h's tables to a program that includes shaders/palette.glsl.
#include "ridge/gpu/shader_program.h"

namespace ridge::render {

// Sets u_land_stops, u_water_stops and u_level_colours of `program` (those it uses).
void setPaletteUniforms(const gpu::ShaderProgram& program);

} // namespace ridge::render
