#version 450
// The fractal-rings paper's decoding (§7) on the GPU: f_{i+1} = T f_i, each sample p_{i+1} =
// s · (mean of its domain block's 2 × 2) + o, the transforms fetched per range block. The
// integer twin of fractal::decodeIterates (src/codec/fractal/pifs.cpp): heights in 1/16 code,
// s = s_q / 32, every division rounded down by floorDiv on non-negative operands, so the codes
// equal the CPU decoder's bit for bit (tests/render/decoders/gpu_fractal_decoder_test.cpp).
//
// One slot's state lives in the buffers at u_slot: f (m × m, the iterate), the transforms
// (4 ints per range block) and the samples (n × n: pinned edge values, interior corrections).
// Passes: 0 the start image (each range block at its fixed point o / (1 − s), edges pinned),
// 1 T f into the scratch image, 2 the scratch back into f (pinned edges kept), 3 the codes:
// the iterate rounded, plus q · (2E + 1) inside, clamped to 16 bits.
layout(local_size_x = 8, local_size_y = 8) in;

layout(std430, binding = 1) buffer State { int f[]; };
layout(std430, binding = 2) readonly buffer Transforms { ivec4 transforms[]; };
layout(std430, binding = 3) readonly buffer Samples { int samples[]; };
layout(std430, binding = 4) buffer Scratch { int next_f[]; };
layout(binding = 5, r16ui) uniform writeonly uimage2DArray u_out;

uniform int u_pass;
uniform int u_n;      // samples per side
uniform int u_m;      // padded side, 4·⌈n/4⌉
uniform int u_ranges; // range blocks per side, m / 4
uniform int u_slot;
uniform int u_layer;
uniform int u_pinned; // 1: edges pinned (bounded mode)
uniform int u_step;   // 2E + 1

const int kRangeSide = 4;
const int kScaleDenominator = 32;
const int kFractionBits = 4;
const int kMaxValue = 65535 << kFractionBits;

int floorDiv(int a, int b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }

bool isEdge(ivec2 p) { return p.x == 0 || p.y == 0 || p.x == u_n - 1 || p.y == u_n - 1; }

void main()
{
    const ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    const int side = u_pass == 3 ? u_n : u_m;
    if (p.x >= side || p.y >= side)
        return;
    const int state = u_slot * u_m * u_m;
    const int at = state + p.y * u_m + p.x;
    const int sample_base = u_slot * u_n * u_n;
    const bool pinned = u_pinned != 0 && p.x < u_n && p.y < u_n && isEdge(p);
    const ivec4 t = transforms[u_slot * u_ranges * u_ranges + (p.y / kRangeSide) * u_ranges +
                               p.x / kRangeSide];
    if (u_pass == 0) {
        f[at] = pinned ? samples[sample_base + p.y * u_n + p.x] << kFractionBits
                       : clamp(floorDiv(t.w * (kScaleDenominator << kFractionBits),
                                        kScaleDenominator - t.z),
                               0, kMaxValue);
    } else if (u_pass == 1) {
        const ivec2 d = t.xy * kRangeSide + 2 * (p % kRangeSide);
        const int i = state + d.y * u_m + d.x;
        const int sum4 = f[i] + f[i + 1] + f[i + u_m] + f[i + u_m + 1];
        next_f[p.y * u_m + p.x] = clamp(floorDiv(t.z * sum4, 4 * kScaleDenominator) +
                                            t.w * (1 << kFractionBits),
                                        0, kMaxValue);
    } else if (u_pass == 2) {
        if (!pinned)
            f[at] = next_f[p.y * u_m + p.x];
    } else {
        int code = min(floorDiv(f[at] + (1 << (kFractionBits - 1)), 1 << kFractionBits), 65535);
        if (u_pinned != 0 && !isEdge(p))
            code = clamp(code + samples[sample_base + p.y * u_n + p.x] * u_step, 0, 65535);
        imageStore(u_out, ivec3(p, u_layer), uvec4(uint(code)));
    }
}
