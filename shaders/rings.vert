#version 450 core
// Scheme "rings" (Erra, Scarano & Guida, §4–6): a tile of the rings structure drawn as one of
// the static vertex grids, heights by displacement from its level's patch. Each vertex carries
// the paper's 4-tuple (x, z, y_pos, w_odd): grid column and row, where it lies (inside, an
// edge, a corner: lod::EdgePosition) and whether it is odd along its edge. An edge that borders
// a coarser tile is stitched (Figure 6): its odd vertices move onto the previous even one (the
// triangle between them degenerates and is not rasterised) and all of its vertices take their
// heights from the coarser level, so both tiles meet at bit-identical vertices with no skirt.
// Which edges a tile stitches comes from its orientation through the paper's look-up table
// (u_stitch_table), or, where the table does not apply (the terrain's border, a cover lowered
// while streaming), from the tile's own mask.
#include "terrain_common.glsl"

uniform int u_instance_offset; // first instance of this draw (GL 4.5 has no gl_BaseInstance)
uniform int u_vertex_step;     // d: level samples per grid cell
uniform int u_stitch_table[9]; // lod::kStitchTable: orientation -> stitched edge positions

// std430 mirror of RingsTileRecord in src/render/schemes/rings_scheme.cpp.
struct RingsTile {
    ivec2 sample_offset;  // the tile's sample (0, 0) in its level's patch (layer)
    ivec2 coarse_offset;  // the same in the coarser level's patch (coarse_layer)
    int coarse_layer;     // −1 when nothing is stitched
    int stitch;           // bit 16: orientation in bits 0..3 (table); else EdgePosition bits
    int cells;            // grid cells a side
    int pad;
};
layout(std430, binding = 3) readonly buffer RingsTiles { RingsTile tiles[]; };

layout(location = 0) in ivec4 a_vertex; // (x, z, y_pos, w_odd)

out Vertex {
    vec3 position;
    vec3 texcoord;
    vec2 cell;
    flat int level;
    flat int layer;
    flat float factor;
    flat int skirt;
} v;
out Capture {
    vec3 tf_position;
    flat int tf_instance;
    flat int tf_skirt;
} capture;

precise gl_Position;

const int kUp = 1, kRight = 2, kDown = 3, kLeft = 4; // edge y_pos; corners are 5..8

void main() {
    int instance = gl_InstanceID + u_instance_offset;
    PatchInstance p = instances[instance];
    RingsTile t = tiles[instance];
    int mask = (t.stitch & 0x10000) != 0 ? u_stitch_table[t.stitch & 15] : (t.stitch & 255);
    ivec2 g = a_vertex.xy;
    int y_pos = a_vertex.z;
    bool stitched = y_pos != 0 && (mask & (1 << (y_pos - 1))) != 0;
    if (stitched && a_vertex.w != 0) {
        // Onto the previous even vertex along the edge.
        if (y_pos == kUp || y_pos == kDown)
            g.x -= 1;
        else
            g.y -= 1;
    }
    ivec2 own = t.sample_offset + g * u_vertex_step;
    precise float z = stitched ? sampleHeight(t.coarse_layer, t.coarse_offset + (g * u_vertex_step) / 2)
                               : sampleHeight(p.layer, own);
    vec3 up;
    precise vec3 position = framePoint(p.origin + g * p.step, z, up);
    v.position = position;
    v.texcoord = vec3((vec2(own) + 0.5) / float(u_patch_cells + 1), float(p.layer));
    v.cell = vec2(own);
    v.level = p.level;
    v.layer = p.layer;
    v.factor = float(u_block_cells);
    v.skirt = 0;
    capture.tf_position = position;
    capture.tf_instance = instance;
    capture.tf_skirt = 0;
    gl_Position = u_view_projection * vec4(position, 1.0);
}
