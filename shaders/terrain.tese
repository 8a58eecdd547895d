#version 450 core
// Tessellation evaluation: snaps each generated vertex to its height-map sample and displaces
// it. Factors are b / 2^d, so every vertex falls on a sample; rounding the domain coordinate
// to an integer sample makes vertices shared by two blocks (or a block and a skirt)
// bit-identical, whatever the tessellator's float coordinates are.
#include "terrain_common.glsl"

layout(quads, equal_spacing, ccw) in;

precise gl_Position;

patch in ivec2 tc_start;
patch in ivec2 tc_axis;
patch in int tc_instance;
patch in float tc_factor;

out Vertex {
    vec3 position;      // camera-relative
    vec3 texcoord;      // normal-map uv and layer
    vec2 cell;          // patch cell coordinates (clipping to the valid extent)
    flat int level;
    flat int layer;     // texture-array slot of the drawn patch (heights, normals)
    flat float factor;  // interior tessellation factor
    flat int skirt;     // 1 for skirts
} v;
// Transform-feedback capture (tests): position, patch instance, 1 for skirts (2 on a foot).
out Capture {
    vec3 tf_position;
    flat int tf_instance;
    flat int tf_skirt;
} capture;

void main() {
    PatchInstance p = instances[tc_instance];
    int b = u_block_cells;
    bool skirt = tc_axis != ivec2(0);
    ivec2 sample_ij = skirt ? tc_start + tc_axis * int(round(gl_TessCoord.x * float(b)))
                            : tc_start + ivec2(round(gl_TessCoord.xy * float(b)));
    // One code path and `precise` (no contraction into FMAs that could differ between call
    // sites): a vertex shared by a block and a skirt, or by two blocks, is bit-identical.
    vec3 up;
    precise vec3 position = drawnPosition(p, sample_ij, up);
    if (skirt) {
        // v = 0 on the patch border, 1 at the skirt's foot, skirt_depth below along the local
        // up (exactly at v = 1: feet of neighbouring segments must be bit-identical).
        if (gl_TessCoord.y >= 1.0)
            position = lowered(position, up, p.skirt_depth);
        else if (gl_TessCoord.y > 0.0)
            position = lowered(position, up, p.skirt_depth * gl_TessCoord.y);
    }
    float n = float(u_patch_cells + 1);
    v.position = position;
    v.texcoord = vec3((vec2(sample_ij) + 0.5) / n, float(p.layer));
    v.cell = vec2(sample_ij);
    v.level = p.level;
    v.layer = p.layer;
    v.factor = tc_factor;
    v.skirt = skirt ? 1 : 0;
    capture.tf_position = position;
    capture.tf_instance = tc_instance;
    capture.tf_skirt = skirt ? (gl_TessCoord.y >= 1.0 ? 2 : 1) : 0;
    gl_Position = u_view_projection * vec4(position, 1.0);
}
