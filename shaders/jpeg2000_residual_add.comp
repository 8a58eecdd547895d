#version 450
// The GPU half of the JPEG2000 paper's decoding (§4): the CPU extracts the difference layer
// D̂ from the JPEG 2000 codestream; here the prediction is formed from the resident parent and
// D̂, read as a normalized texture and scaled to [d_min, d_min + (2^n − 1)·step], is added.
// The paper samples the parent with bilinear filtering; this pass fetches the four parent
// texels and averages them in integers (the same (a+b+c+d+2)>>2 as the CPU), because filter
// weights are only guaranteed to a few fractional bits and the result must equal the CPU
// decoder's bit for bit (tests/render/gpu_jpeg2000_decoder_test.cpp).
layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = 0) uniform usampler2DArray u_heights;          // parent codes (R16UI)
layout(binding = 1, r16ui) uniform writeonly uimage2DArray u_out;
layout(binding = 2) uniform sampler2D u_difference;             // D̂ as UNORM (R8 or R16)
layout(std430, binding = 3) readonly buffer Edges { int edges[]; }; // top, bottom, left, right

uniform int u_n;
uniform int u_child_index;
uniform int u_parent_layer;
uniform int u_child_layer;
uniform int u_direct;   // 1: the heights themselves (no prediction)
uniform int u_d_min;
uniform int u_step;
uniform int u_unorm_max; // 255 (R8) or 65535 (R16): the texture's normalization, not 2^bits − 1
uniform ivec2 u_region; // coded samples; beyond them the last column and row repeat

int parentAt(ivec2 q)
{
    return int(texelFetch(u_heights, ivec3(q, u_parent_layer), 0).r);
}

void main()
{
    const ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (p.x >= u_n || p.y >= u_n)
        return;
    const ivec2 s = min(p, u_region - 1);
    int prediction = 0;
    if (u_direct == 0) {
        const int half_n = (u_n - 1) / 2;
        const ivec2 i = ivec2(u_child_index & 1, u_child_index >> 1) * half_n + s / 2;
        const ivec2 j = i + (s & 1);
        prediction = (parentAt(i) + parentAt(ivec2(j.x, i.y)) + parentAt(ivec2(i.x, j.y)) +
                      parentAt(j) + 2) >> 2;
    }
    int d;
    if (s.y == 0)
        d = edges[s.x];
    else if (s.y == u_n - 1)
        d = edges[u_n + s.x];
    else if (s.x == 0)
        d = edges[2 * u_n + s.y];
    else if (s.x == u_n - 1)
        d = edges[3 * u_n + s.y];
    else // the hardware's [0, 1] back to d̂ (exact: |error| < 2^-24 · 65535), then scaled
        d = u_d_min + int(round(texelFetch(u_difference, s, 0).r * float(u_unorm_max))) * u_step;
    imageStore(u_out, ivec3(p, u_child_layer), uvec4(uint(clamp(prediction + d, 0, 65535))));
}
