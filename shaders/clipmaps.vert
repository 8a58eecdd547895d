#version 450 core
// Scheme clipmaps (the clipmaps thesis §3.3–3.5, after Asirvatham & Hoppe): one footprint
// piece of one level, its vertices lifted from the level's texture (toroidal: window sample
// (i, j) at texel (i mod N, j mod N)). In the transition region near the window's perimeter
// the height blends into the next coarser level's surface (Losasso & Hoppe: z' = (1 − α) z +
// α z_coarse, α = clamp((d − ((n − 1)/2 − w − 2))/w, 0, 1), d the Chebyshev distance to the
// viewer in the level's cells), so that on the perimeter (α = 1) it is the coarser surface:
// even vertices its samples, bit for bit, odd ones the midpoint of its edge. Positions come
// from framePoint like every scheme's: an integer offset from the anchor sample near the
// camera, mapped through the terrain frame — no 3-D vertex texture, no precision limit.
#include "terrain_common.glsl"

uniform int u_instance_offset; // first instance of this draw (GL 4.5 has no gl_BaseInstance)
uniform int u_texture_size;    // N = n + 1
uniform int u_window;          // n
uniform vec2 u_transition;     // ((n − 1)/2 − w − 2, w): where α starts, and the region's width

// std430 mirror of ClipmapPieceRecord in src/render/schemes/clipmaps_scheme.cpp.
struct ClipmapPiece {
    ivec2 texel;        // texel of the window's sample (0, 0) in the level's texture
    ivec2 coarse_texel; // texel of that sample in the coarser level's texture
    vec2 viewer;        // the viewer in the window's cells
    ivec2 local;        // the piece's vertex (0, 0) in the window's cells
    int coarse_layer;   // the coarser level; −1 on the coarsest drawn (no transition)
    int kind;           // lod::FootprintKind
};
layout(std430, binding = 3) readonly buffer ClipmapPieces { ClipmapPiece pieces[]; };
layout(binding = 11) uniform usampler2DArray u_levels; // RG16UI: code, flags

layout(location = 0) in uvec2 a_vertex; // cells from the piece's corner

out Vertex {
    vec3 position;
    vec3 texcoord; // the window's cells (x, y) and α
    vec2 cell;     // the piece's cells (the clip stage's coordinates)
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

float levelHeight(int layer, ivec2 texel) {
    uint code = texelFetch(u_levels, ivec3(texel & ivec2(u_texture_size - 1), layer), 0).r;
    precise float z = u_height_offset + u_height_scale * float(code);
    return z;
}

void main() {
    int instance = gl_InstanceID + u_instance_offset;
    PatchInstance p = instances[instance];
    ClipmapPiece piece = pieces[instance];
    ivec2 corner = ivec2(a_vertex);
    ivec2 w = piece.local + corner; // the window's cells
    precise float z = levelHeight(p.layer, piece.texel + w);
    float alpha = 0.0;
    if (piece.coarse_layer >= 0) {
        vec2 d = abs(vec2(w) - piece.viewer);
        alpha = clamp((max(d.x, d.y) - u_transition.x) / u_transition.y, 0.0, 1.0);
        // On the perimeter whatever the rounding: the coarser level's surface exactly.
        if (w.x == 0 || w.y == 0 || w.x == u_window - 1 || w.y == u_window - 1)
            alpha = 1.0;
        if (alpha > 0.0) {
            // The window's sample (0, 0) is on the coarser grid: even cells are its samples.
            ivec2 c0 = piece.coarse_texel + (w >> 1), odd = w & 1;
            precise float zc = levelHeight(piece.coarse_layer, c0);
            // A cell's centre: the middle of the coarser cell's diagonal b–c (its triangles
            // a b c, b d c), so the target is the coarser mesh's surface there exactly.
            if (odd.x != 0 && odd.y != 0)
                zc = 0.5 * (levelHeight(piece.coarse_layer, c0 + ivec2(1, 0)) +
                            levelHeight(piece.coarse_layer, c0 + ivec2(0, 1)));
            else if (odd.x != 0 || odd.y != 0)
                zc = 0.5 * (zc + levelHeight(piece.coarse_layer, c0 + odd));
            z = alpha == 1.0 ? zc : mix(z, zc, alpha);
        }
    }
    vec3 up;
    precise vec3 position = framePoint(p.origin + corner * p.step, z, up);
    v.position = position;
    v.texcoord = vec3(vec2(w), alpha);
    v.cell = vec2(corner);
    v.level = p.level;
    v.layer = p.layer;
    v.factor = float(1 << (piece.kind + 1)); // the heat-map mode colours footprints by kind
    v.skirt = 0;
    capture.tf_position = position;
    capture.tf_instance = instance;
    capture.tf_skirt = 0;
    gl_Position = u_view_projection * vec4(position, 1.0);
}
