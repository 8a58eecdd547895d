#version 450 core
// Tessellation block errors λ^(d) of one resident patch, derived on the GPU from its height
// map, for patches reconstructed on the GPU from an archive that does not store λ. The twin
// of computeTessellationBlockErrors (src/pyramid/tessellation_block_errors.cpp): the same
// integer deviations, the same cell per sample, the same rounding to metres (fp64), so the
// result is bit-identical (tests/render check it).
//
// One invocation per block (s, r): λ^(1..D) into one RGBA32F texel; the patch's largest λ
// goes to lambda_max[u_layer] (float bits compare as uints: λ >= 0) for the skirt depths.
layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = 0) uniform usampler2DArray u_heights;
layout(binding = 2, rgba32f) uniform writeonly image2DArray u_block_errors;
layout(std430, binding = 3) buffer LambdaMax { uint lambda_max[]; };

uniform int u_layer;
uniform int u_n;               // samples per patch side
uniform int u_block_cells;     // b
uniform int u_blocks_per_side; // B
uniform int u_levels;          // D stored in the texel (<= 4)
uniform double u_height_scale; // metres per code

int code(int x, int y) { return int(texelFetch(u_heights, ivec3(x, y, u_layer), 0).r); }

// |sample − each diagonal triangulation of its simplified cell|, times st (exact integers).
int deviation(int x, int y, int d) {
    int st = 1 << d;
    int cx = min((x >> d) << d, u_n - 1 - st);
    int cy = y == 0 ? 0 : ((y - 1) >> d) << d; // rows take the cell above (as the CPU walks)
    int u = x - cx, v = y - cy;
    int a = code(cx, cy), b = code(cx + st, cy), c = code(cx, cy + st), e = code(cx + st, cy + st);
    int k = a + e - b - c;
    int plane = a * st + (b - a) * u + (c - a) * v;
    int h = code(x, y) * st;
    int diag_ae = plane + k * min(u, v);
    int diag_bc = plane + k * max(0, u + v - st);
    return max(abs(h - diag_ae), abs(h - diag_bc));
}

void main() {
    ivec2 block = ivec2(gl_GlobalInvocationID.xy); // (s, r)
    if (block.x >= u_blocks_per_side || block.y >= u_blocks_per_side)
        return;
    vec4 lambda = vec4(0.0);
    for (int d = 1; d <= u_levels; ++d) {
        int worst = 0;
        for (int y = block.y * u_block_cells; y <= (block.y + 1) * u_block_cells; ++y)
            for (int x = block.x * u_block_cells; x <= (block.x + 1) * u_block_cells; ++x)
                worst = max(worst, deviation(x, y, d));
        // CPU: float(double(worst) / st), then float(that · scale) in double.
        float in_codes = float(worst) / float(1 << d);
        lambda[d - 1] = float(double(in_codes) * u_height_scale);
    }
    imageStore(u_block_errors, ivec3(block, u_layer), lambda);
    float m = max(max(lambda.x, lambda.y), max(lambda.z, lambda.w));
    atomicMax(lambda_max[u_layer], floatBitsToUint(m));
}
