#version 450 core
// GPU half of the progressive codec's decoding (hardware-tessellation paper, "Implementation
// Details"): the CPU entropy-decodes a child patch's residuals; these passes refine the parent
// and add the predictions, writing the child's height map straight into its texture-array
// layer. Integer arithmetic only, the same as src/codec/progressive_reconstruction.cpp, so
// the result is bit-identical to the CPU decoder (tests/render check every patch).
//
// Passes (u_pass), each one dispatch over the samples of its class:
//   0 R (even x, even y): q = Q_child(parent code) + r     — the refined parent samples
//   1 A (odd x,  even y): q = P(row of R) − r
//   2 B (even x, odd y):  q = P(column of R) − r
//   3 C (odd x,  odd y):  q = P(A, B) − r
//   4 store:              code = clamp(step · q, 0, 65535), beyond the coded region the
//                         nearest sample inside it (payload v2 codes only the region that
//                         covers the valid extent; v1's region is the whole patch)
layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = 0) uniform usampler2DArray u_heights; // the parent's codes
layout(binding = 1, r16ui) uniform writeonly uimage2DArray u_child_heights;
layout(std430, binding = 1) readonly buffer Residuals { int residuals[]; };
uniform int u_residual_bits; // 32, or 16: two residuals per int, the first in the low half

int residual(int i) {
    return u_residual_bits == 16 ? bitfieldExtract(residuals[i >> 1], (i & 1) * 16, 16)
                                 : residuals[i];
}
layout(std430, binding = 2) buffer Bins { int q[]; };

uniform int u_pass;
uniform int u_n;           // samples per side, 2^m + 1
uniform int u_child_index; // quadrant in the parent: (x & 1) | (y & 1) << 1
uniform int u_parent_layer;
uniform int u_child_layer;
uniform int u_step;        // the child level's quantizer: s_k = 2·e_k + 1
uniform int u_bound;       // e_k
uniform int u_cubic;       // OddPredictor::Cubic (else Bilinear)
uniform ivec2 u_region;    // the coded region [0, w) × [0, h) (CodedRegion), odd sides
// v2's least-squares corrections of this pass's class (PredictorWeights), when u_correct:
// P = P0 + (Σ w_i · clamp(s_i − P0, ±32767) + 2048) >> 12 where all 12 taps lie inside the
// region (the taps and margins of kCorrectionTaps in progressive_reconstruction.h).
uniform int u_correct;
uniform int u_weights[12];

const ivec2 kTaps[36] = ivec2[36](
    ivec2(-1, 0), ivec2(1, 0), ivec2(-3, 0), ivec2(3, 0), ivec2(-1, -2), ivec2(1, -2),
    ivec2(-1, 2), ivec2(1, 2), ivec2(-3, -2), ivec2(3, -2), ivec2(-3, 2), ivec2(3, 2),
    ivec2(0, -1), ivec2(0, 1), ivec2(0, -3), ivec2(0, 3), ivec2(-2, -1), ivec2(2, -1),
    ivec2(-2, 1), ivec2(2, 1), ivec2(-1, -1), ivec2(1, -1), ivec2(-1, 1), ivec2(1, 1),
    ivec2(0, -1), ivec2(0, 1), ivec2(-1, 0), ivec2(1, 0), ivec2(-1, -1), ivec2(1, -1),
    ivec2(-1, 1), ivec2(1, 1), ivec2(0, -3), ivec2(0, 3), ivec2(-3, 0), ivec2(3, 0));
const ivec2 kMargin[3] = ivec2[3](ivec2(3, 2), ivec2(2, 3), ivec2(3, 3));

int at(int x, int y) { return q[y * u_n + x]; }

// 16 × the value halfway between samples pos − 1 and pos + 1 of a line (see midpoint16 in
// progressive_reconstruction.cpp): cubic inside, quadratic at the ends, linear when short.
// The line ends where the coded region does (len).
int midpoint16(ivec2 origin, ivec2 dir, int pos, int len) {
    int a = at(origin.x + dir.x * (pos - 1), origin.y + dir.y * (pos - 1));
    int b = at(origin.x + dir.x * (pos + 1), origin.y + dir.y * (pos + 1));
    bool has_before = pos - 3 >= 0, has_after = pos + 3 < len;
    if (has_before && has_after)
        return 9 * (a + b) - at(origin.x + dir.x * (pos - 3), origin.y + dir.y * (pos - 3)) -
               at(origin.x + dir.x * (pos + 3), origin.y + dir.y * (pos + 3));
    if (has_after)
        return 6 * a + 12 * b - 2 * at(origin.x + dir.x * (pos + 3), origin.y + dir.y * (pos + 3));
    if (has_before)
        return 12 * a + 6 * b - 2 * at(origin.x + dir.x * (pos - 3), origin.y + dir.y * (pos - 3));
    return 8 * (a + b);
}

int predictOdd(int x, int y) {
    int cls = (x & 1) | ((y & 1) << 1);
    if (cls == 1) { // A
        if (u_cubic == 0)
            return (at(x - 1, y) + at(x + 1, y) + 1) >> 1;
        return (midpoint16(ivec2(0, y), ivec2(1, 0), x, u_region.x) + 8) >> 4;
    }
    if (cls == 2) { // B
        if (u_cubic == 0)
            return (at(x, y - 1) + at(x, y + 1) + 1) >> 1;
        return (midpoint16(ivec2(x, 0), ivec2(0, 1), y, u_region.y) + 8) >> 4;
    }
    // C
    if (u_cubic == 0)
        return (at(x - 1, y - 1) + at(x + 1, y - 1) + at(x - 1, y + 1) + at(x + 1, y + 1) + 2) >> 2;
    return (midpoint16(ivec2(0, y), ivec2(1, 0), x, u_region.x) +
            midpoint16(ivec2(x, 0), ivec2(0, 1), y, u_region.y) + 16) >> 5;
}

int correction(int x, int y, int cls, int p0) {
    ivec2 m = kMargin[cls - 1];
    if (u_correct == 0 || x < m.x || x >= u_region.x - m.x || y < m.y || y >= u_region.y - m.y)
        return 0;
    int sum = 0;
    for (int i = 0; i < 12; ++i) {
        ivec2 t = kTaps[(cls - 1) * 12 + i];
        sum += u_weights[i] * clamp(at(x + t.x, y + t.y) - p0, -32767, 32767);
    }
    return (sum + 2048) >> 12;
}

void main() {
    // Thread (i, j) handles sample (2i + x0, 2j + y0) of its pass, or (i, j) when storing.
    ivec2 id = ivec2(gl_GlobalInvocationID.xy);
    if (u_pass == 4) {
        if (id.x >= u_n || id.y >= u_n)
            return;
        // clamp(q) first: step · q then fits in 32 bits and clamps like the CPU's 64-bit product.
        ivec2 from = min(id, u_region - 1);
        int bins = clamp(q[from.y * u_n + from.x], -1, 65535 / u_step + 1);
        imageStore(u_child_heights, ivec3(id, u_child_layer), uvec4(uint(clamp(u_step * bins, 0, 65535))));
        return;
    }
    ivec2 offset = ivec2(u_pass & 1, u_pass >> 1);
    ivec2 xy = 2 * id + offset;
    if (xy.x >= u_region.x || xy.y >= u_region.y)
        return;
    int i = xy.y * u_n + xy.x;
    if (u_pass == 0) {
        int half_n = (u_n - 1) / 2;
        ivec2 parent = ivec2((u_child_index & 1) * half_n, (u_child_index >> 1) * half_n) + xy / 2;
        int code = int(texelFetch(u_heights, ivec3(parent, u_parent_layer), 0).r);
        q[i] = (code + u_bound) / u_step + residual(i);
    } else {
        int p0 = predictOdd(xy.x, xy.y);
        q[i] = p0 + correction(xy.x, xy.y, u_pass, p0) - residual(i);
    }
}
