#version 450 core
// Runs the edge rules of shaders/edge_tessellation.glsl on a batch of cases, so that tests can
// compare them with ridge::lod::edgeSimplification (their C++ twin): per case, d at the centre
// alone (the paper's test) and d of the whole edge under RIDGE_TESSELLATION_RULE.
#include "terrain_common.glsl"
#include "edge_tessellation.glsl"

layout(local_size_x = 64) in;

// Per case: endpoint a (w: Err(P)), centre, endpoint b, then Λ^(1..4).
layout(std430, binding = 1) readonly buffer Cases { vec4 cases[]; };
layout(std430, binding = 2) writeonly buffer Results { ivec2 simplification[]; };

uniform int u_case_count;

void main() {
    int i = int(gl_GlobalInvocationID.x);
    if (i >= u_case_count)
        return;
    vec4 errors = cases[4 * i + 3];
    const vec3 up = vec3(0.0, 0.0, 1.0); // the plane's: the C++ twin measures along +z
    simplification[i] = ivec2(edgeSimplification(cases[4 * i + 1].xyz, up, errors),
                              edgeSimplification(cases[4 * i].xyz, cases[4 * i + 1].xyz,
                                                 cases[4 * i + 2].xyz, up, errors,
                                                 cases[4 * i].w));
}
