#version 450 core
// Reads an integer map at fractional coordinates through shaders/texel_quad.glsl, so that a
// test can compare it with a CPU bilinear of the same texels.
#include "texel_quad.glsl"

layout(local_size_x = 64) in;

layout(binding = 0) uniform usampler2DArray u_map;
// Per case: cell coordinates (x, y), layer (z).
layout(std430, binding = 1) readonly buffer Cases { vec4 cases[]; };
layout(std430, binding = 2) writeonly buffer Results { float value[]; };

uniform int u_case_count;
uniform int u_cells;

void main() {
    int i = int(gl_GlobalInvocationID.x);
    if (i >= u_case_count)
        return;
    vec2 f;
    vec4 q = vec4(gatherQuad(u_map, int(cases[i].z), cases[i].xy, u_cells, f));
    value[i] = bilinear(q, f);
}
