#version 450 core
// Normal map of one resident patch, computed on the GPU when it becomes resident (paper,
// "Implementation Details"). Central differences inside, one-sided at the patch border (the
// paper compresses (2^n+3)^2 patches for seamless borders; ridge archives store 2^n+1).
layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = 0) uniform usampler2DArray u_heights;
layout(binding = 0, rgba8_snorm) uniform writeonly image2DArray u_normal_image;

uniform int u_layer;
uniform int u_size;           // samples per side
uniform vec2 u_cell_metres;   // metres per cell along i (east) and j (south)
uniform float u_height_scale; // metres per code

float h(ivec2 ij) {
    ij = clamp(ij, ivec2(0), ivec2(u_size - 1));
    return u_height_scale * float(texelFetch(u_heights, ivec3(ij, u_layer), 0).r);
}

void main() {
    ivec2 ij = ivec2(gl_GlobalInvocationID.xy);
    if (ij.x >= u_size || ij.y >= u_size)
        return;
    ivec2 lo = max(ij - 1, ivec2(0)), hi = min(ij + 1, ivec2(u_size - 1));
    float dzdi = (h(ivec2(hi.x, ij.y)) - h(ivec2(lo.x, ij.y))) / (float(hi.x - lo.x) * u_cell_metres.x);
    float dzdj = (h(ivec2(ij.x, hi.y)) - h(ivec2(ij.x, lo.y))) / (float(hi.y - lo.y) * u_cell_metres.y);
    // j grows southwards: dz/dy(north) = −dz/dj.
    vec3 n = normalize(vec3(-dzdi, dzdj, 1.0));
    imageStore(u_normal_image, ivec3(ij, u_layer), vec4(n, 0.0));
}
