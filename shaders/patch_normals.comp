#version 450 core
// Normal map of one resident patch, computed on the GPU when it becomes resident (paper,
// "Implementation Details"). Central differences everywhere, over the patch's heights with a
// one-sample ring borrowed from its same-level neighbours (stream/bordered_patch.h), so that
// both sides of a seam between patches of one level get the same normals.
layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = 0) uniform sampler2D u_bordered; // (size+2)^2 heights in code units
layout(binding = 0, rgba8_snorm) uniform writeonly image2DArray u_normal_image;

uniform int u_layer;
uniform int u_size;           // samples per side
uniform vec2 u_cell_metres;   // metres per cell along i (east) and j (south)
uniform float u_height_scale; // metres per code

float h(ivec2 ij) {
    return u_height_scale * texelFetch(u_bordered, ij + 1, 0).r;
}

void main() {
    ivec2 ij = ivec2(gl_GlobalInvocationID.xy);
    if (ij.x >= u_size || ij.y >= u_size)
        return;
    float dzdi = (h(ij + ivec2(1, 0)) - h(ij - ivec2(1, 0))) / (2.0 * u_cell_metres.x);
    float dzdj = (h(ij + ivec2(0, 1)) - h(ij - ivec2(0, 1))) / (2.0 * u_cell_metres.y);
    // j grows southwards: dz/dy(north) = −dz/dj.
    vec3 n = normalize(vec3(-dzdi, dzdj, 1.0));
    imageStore(u_normal_image, ivec3(ij, u_layer), vec4(n, 0.0));
}
