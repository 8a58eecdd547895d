#version 450 core
// Chunked LOD and brute-force baselines (Ulrich 2000; the yardsticks of the hardware-
// tessellation paper): each selected patch drawn as one precomputed full-resolution mesh of its
// level — the same index buffer for every patch, heights from the same texture arrays — with
// a skirt around it. Vertex ids 0 .. n²−1 are the patch's samples, n² + k the foot of the k-th
// border sample in ring order (north row west to east, east column, south row east to west,
// west column).
#include "terrain_common.glsl"

uniform int u_instance_offset; // first instance of this draw (GL 4.5 has no gl_BaseInstance)

out Vertex {
    vec3 position;
    vec3 texcoord;
    vec2 cell;
    flat int level;
    flat int layer;     // texture-array slot of the drawn patch (heights, normals)
    flat float factor;
    flat int skirt;
} v;
out Capture {
    vec3 tf_position;
    flat int tf_instance;
    flat int tf_skirt;
} capture;

precise gl_Position;

ivec2 ringSample(int k, int C) {
    if (k < C) return ivec2(k, 0);
    if (k < 2 * C) return ivec2(C, k - C);
    if (k < 3 * C) return ivec2(C - (k - 2 * C), C);
    return ivec2(0, C - (k - 3 * C));
}

void main() {
    int instance = gl_InstanceID + u_instance_offset;
    PatchInstance p = instances[instance];
    int C = u_patch_cells, n = C + 1;
    bool foot = gl_VertexID >= n * n;
    ivec2 sample_ij = foot ? ringSample(gl_VertexID - n * n, C) : ivec2(gl_VertexID % n, gl_VertexID / n);
    vec3 up;
    precise vec3 position = drawnPosition(p, sample_ij, up);
    if (foot)
        position = lowered(position, up, p.skirt_depth);
    v.position = position;
    v.texcoord = vec3((vec2(sample_ij) + 0.5) / float(n), float(p.layer));
    v.cell = vec2(sample_ij);
    v.level = p.level;
    v.layer = p.layer;
    v.factor = float(u_block_cells); // full resolution everywhere
    v.skirt = foot ? 1 : 0;
    capture.tf_position = position;
    capture.tf_instance = instance;
    capture.tf_skirt = foot ? 2 : 0;
    gl_Position = u_view_projection * vec4(position, 1.0);
}
