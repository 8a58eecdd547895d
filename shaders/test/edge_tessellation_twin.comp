#version 450 core
// Runs edgeSimplification of shaders/edge_tessellation.glsl on a batch of cases, so that
// tests can compare it with ridge::lod::edgeSimplification (its C++ twin).
#include "terrain_common.glsl"
#include "edge_tessellation.glsl"

layout(local_size_x = 64) in;

layout(std430, binding = 1) readonly buffer Cases { vec4 cases[]; }; // centre, then Λ^(1..4)
layout(std430, binding = 2) writeonly buffer Results { int simplification[]; };

uniform int u_case_count;

void main() {
    int i = int(gl_GlobalInvocationID.x);
    if (i >= u_case_count)
        return;
    simplification[i] = edgeSimplification(cases[2 * i].xyz, cases[2 * i + 1]);
}
