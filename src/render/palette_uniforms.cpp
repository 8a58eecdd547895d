#include "palette_uniforms.h"

#include "ridge/core/terrain_palette.h"

#include <vector>

namespace ridge::render {

namespace {

template <size_t N> std::vector<float> packStops(const std::array<palette::Stop, N>& stops)
{
    std::vector<float> packed;
    for (const palette::Stop& s : stops)
        packed.insert(packed.end(), {s.t, s.colour.r, s.colour.g, s.colour.b});
    return packed;
}

} // namespace

void setPaletteUniforms(const gpu::ShaderProgram& program)
{
    const GLuint id = program.id();
    const std::vector<float> land = packStops(palette::kLandStops);
    const std::vector<float> water = packStops(palette::kWaterStops);
    glProgramUniform4fv(id, program.uniform("u_land_stops"), GLsizei(palette::kLandStops.size()),
                        land.data());
    glProgramUniform4fv(id, program.uniform("u_water_stops"), GLsizei(palette::kWaterStops.size()),
                        water.data());
    std::vector<float> levels;
    for (const palette::Rgb& c : palette::kLevelColours)
        levels.insert(levels.end(), {c.r, c.g, c.b});
    glProgramUniform3fv(id, program.uniform("u_level_colours"),
                        GLsizei(palette::kLevelColours.size()), levels.data());
}

} // namespace ridge::render
