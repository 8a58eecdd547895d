#version 450 core
// Decodes compact geomorph vertices with shaders/geomorph_common.glsl, from real vertex
// attributes in the documented formats, and captures the results by transform feedback, so
// tests can compare them with ridge::lod's packers and decoders (their C++ twins).
#include "geomorph_common.glsl"

layout(location = 0) in uvec2 a_block_coord;
layout(location = 1) in uvec2 a_heights;
layout(location = 2) in vec2 a_normal_index;

uniform ivec4 u_geomorph_block; // lod::CompactBlock of the block being drawn
uniform float u_morph;          // t

out vec3 position;
out vec3 normal_analytic;
out vec3 normal_texture;

void main() {
    position = geomorphCompactPosition(a_block_coord, a_heights, u_geomorph_block, u_morph);
    normal_analytic = hemisphereDecode(u_hemisphere_map, a_normal_index);
    normal_texture = hemisphereNormalLookup(a_normal_index);
    gl_Position = vec4(0.0);
}
