#version 450 core
// Terrain shading at texture resolution: colour, water and (except geomorph, below) normals
// come from height and normal maps at the fragment's patch coordinates, not from the mesh, so
// a coarse mesh still shows every sample of its level (a continent on one patch of 184
// triangles keeps its coastline). With texture detail on (u_shading_detail), the maps are
// those of the finest resident patch under the fragment (the shading map, below): the
// triangles stay the drawn patch's, the texels are the finer level's. The colour from them is
// terrain_shading.glsl's (sun, palette, slope, fog, debug modes), shared with clipmaps.frag.
// From the evaluation shader, or from terrain_clip.geom for patches partly outside the
// valid extent (clipped there exactly, with a wall under the cut).
in Vertex {
    vec3 position;      // camera-relative
    vec3 texcoord;      // normal-map uv and layer
    vec2 cell;          // patch sample coordinates: the same at a skirt and the border above it
    flat int level;
    flat int layer;     // texture-array slot of the drawn patch
    flat float factor;  // interior tessellation factor
    flat int skirt;     // 1 for skirts, 2 for the walls on the clipped border
} v;

#include "terrain_common.glsl"
// Kept nodata (docs/FORMAT.md, "Validity mask"): per slot, flags (bit 0: it has a cell mask;
// bit 1: a water bitmap; bit 2: all water), and the mask (1 = drawable) of its C × C cells.
// Slots without nodata never upload a mask.
layout(binding = 4) uniform usampler2DArray u_cell_masks;
layout(binding = 5) uniform usampler1D u_mask_flags;
// Water (docs/FORMAT.md, "Sample flags"): the n × n sample flags of slots with bit 1, water in
// bit 0 of each (none before format 4: RIDGE_WATER_FROM_HEIGHT, below).
layout(binding = 6) uniform usampler2DArray u_water_maps;
#ifndef RIDGE_WATER_FROM_HEIGHT
#error RIDGE_WATER_FROM_HEIGHT is not defined: build terrain programs through SchemePrograms
#endif
#include "geomorph_common.glsl"
#include "palette.glsl"

#include "terrain_shading.glsl"

// The shading map (src/render/shading_map.h, ridge/lod/shading_tiles.h): per slot, 8 × 8
// tiles over its patch, each 0 (shade from the drawn patch) or (slot + 1) | (k << 24), a
// patch k levels finer. Read only with u_shading_detail (texture detail on).
layout(std430, binding = 4) readonly buffer ShadingMap { uint shading_tiles[]; };
uniform bool u_shading_detail;
const int kShadingTiles = 8;

out vec4 frag_colour;

#include "texel_quad.glsl"

// Where the fragment shades from: a slot and coordinates in its patch.
struct ShadingSource {
    int layer;
    vec2 cell;
    bool own; // the drawn patch itself (its interpolated texcoord applies)
};

// The finest resident patch under patch coordinates `cell` of the drawn patch: its tile names
// it and how many levels finer it is (k); its patch covers 2^(3−k) tiles a side, from the
// tile index rounded down to that, and its coordinates are the drawn ones scaled by 2^k.
ShadingSource shadingSource(vec2 cell) {
    ShadingSource s = ShadingSource(v.layer, cell, true);
    if (!u_shading_detail)
        return s;
    float c = float(u_patch_cells);
    ivec2 tile = clamp(ivec2(floor(cell * (float(kShadingTiles) / c))), ivec2(0),
                       ivec2(kShadingTiles - 1));
    uint word = shading_tiles[v.layer * kShadingTiles * kShadingTiles + tile.y * kShadingTiles + tile.x];
    if (word == 0u)
        return s;
    int k = int(word >> 24);
    int span = kShadingTiles >> k; // tiles a side of the finer patch
    vec2 origin = vec2((tile / span) * span) * (c / float(kShadingTiles));
    s.layer = int(word & 0xffffffu) - 1;
    s.cell = clamp((cell - origin) * float(1 << k), vec2(0.0), vec2(c));
    s.own = false;
    return s;
}

// Metres above sea level of a patch's height map at patch coordinates `cell`, bilinear
// between its four samples (the codes are integers: no hardware filtering). At a sample this
// is the sample, as `ridge hillshade` sees it. True metres: the drawn heights divided by the
// exaggeration, so that colours do not change with it.
float textureMetres(int layer, vec2 cell) {
    vec2 f;
    vec4 codes = vec4(gatherQuad(u_heights, layer, cell, u_patch_cells, f));
    precise float z = u_height_offset + u_height_scale * bilinear(codes, f);
    return (z - u_sea_level) / u_exaggeration;
}

// The normal map's, or (RIDGE_VERTEX_NORMALS 1: geomorph) the vertex's own normal where the
// scheme sends one (geomorph.vert): texcoord (u, v, −1) indexes the hemisphere normal texture,
// (nx, ny, −2 − nz) is a normal. geomorph keeps its vertex normals: it draws every sample of the
// patch as a vertex, so they are at texel resolution already, and they are what its vertex
// layouts are measured with. Compiled in, so that the other schemes' fragments do not run the
// other two cases under a mask (llvmpipe).
// Normals are of the true surface; the drawn one, z' = k·z, has the normal
// (−k ∂z/∂x, −k ∂z/∂y, 1) ∝ (k·n.x, k·n.y, n.z).
#ifndef RIDGE_VERTEX_NORMALS
#define RIDGE_VERTEX_NORMALS 0
#endif
vec3 exaggerated(vec3 n) { return normalize(vec3(n.xy * u_exaggeration, n.z)); }
vec3 surfaceNormal(ShadingSource s) {
    if (!s.own) // a finer patch's normal map: sample i at (i + ½) / n
        return exaggerated(normalize(texture(u_normals, vec3((s.cell + 0.5) / float(u_patch_cells + 1),
                                                             float(s.layer))).xyz));
#if RIDGE_VERTEX_NORMALS
    if (v.texcoord.z >= -0.5)
        return exaggerated(normalize(texture(u_normals, v.texcoord).xyz));
    if (v.texcoord.z > -1.5)
        return exaggerated(normalize(hemisphereNormalLookup(v.texcoord.xy)));
    return exaggerated(normalize(vec3(v.texcoord.xy, -2.0 - v.texcoord.z)));
#else
    return exaggerated(normalize(texture(u_normals, v.texcoord).xyz));
#endif
}

// A slot's mask flags (bit 0: a cell mask; bit 1: a water bitmap; bit 2: all water).
uint maskFlags(int layer) { return texelFetch(u_mask_flags, layer, 0).r; }

// Whether the cell at patch coordinates `at` of `layer` may be drawn. Skirts and walls hang
// under a border sample, whose cell coordinate is C at the far border: the clamp gives them
// the border cell, so they vanish with it.
bool cellDrawable(uint flags, int layer, vec2 at) {
    if ((flags & 1u) == 0u)
        return true;
    ivec2 cell = clamp(ivec2(floor(at)), ivec2(0), ivec2(u_patch_cells - 1));
    return texelFetch(u_cell_masks, ivec3(cell, layer), 0).r != 0u;
}

// Whether the surface at patch coordinates `cell` is water: the bilinear blend of its four
// samples' water flags is at least 1/2, so that a coastline is as smooth as the heights'
// surface and lies halfway between a water and a land sample, whatever the decoded heights.
// Archives before format 4 store no flags: RIDGE_WATER_FROM_HEIGHT (compiled in per archive)
// applies the old rule, a height at or below 0 m.
bool waterAt(uint flags, int layer, vec2 cell, float metres) {
#if RIDGE_WATER_FROM_HEIGHT
    return paletteIsWater(metres);
#else
    if ((flags & 4u) != 0u)
        return true;
    if ((flags & 2u) == 0u)
        return false;
    vec2 f;
    vec4 wet = vec4(gatherQuad(u_water_maps, layer, cell, u_patch_cells, f) & uvec4(1u));
    return bilinear(wet, f) >= 0.5;
#endif
}

void main() {
    uint flags = maskFlags(v.layer);
    if (!cellDrawable(flags, v.layer, v.cell))
        discard; // nodata: the terrain ends at the last drawable cell
    if (u_mode == 3) {
        frag_colour = vec4(u_flat_colour, 1.0);
        return;
    }
    // Skirts take the normal and height of the border sample above them (their cell and
    // texcoord are the border's), so that a step between two levels reads as part of the
    // slope, and a skirt hanging through 0 m is not painted as sea.
    ShadingSource s = shadingSource(v.cell);
    uint shading_flags = s.own ? flags : maskFlags(s.layer);
    if (!s.own && !cellDrawable(shading_flags, s.layer, s.cell)) {
        // The finer level keeps nodata where the drawn one has a drawable cell: its fill
        // heights are not terrain, so the drawn patch's texels shade here.
        s = ShadingSource(v.layer, v.cell, true);
        shading_flags = flags;
    }
    float metres = textureMetres(s.layer, s.cell);
    frag_colour = shadeTerrain(v.position, surfaceNormal(s), metres,
                               waterAt(shading_flags, s.layer, s.cell, metres), v.level, v.factor,
                               v.skirt == 2);
}
