#version 450 core
// Terrain shading at texture resolution: colour, water and (except geomorph, below) normals
// come from the drawn patch's own height and normal maps at the fragment's patch coordinates,
// not from the mesh, so a coarse mesh still shows every sample of its level (a continent on
// one patch of 184 triangles keeps its coastline). The colour from them is
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

out vec4 frag_colour;

#include "texel_quad.glsl"

// Metres above sea level of the patch's height map at patch coordinates `cell`, bilinear
// between its four samples (the codes are integers: no hardware filtering). At a sample this
// is the sample, as `ridge hillshade` sees it. True metres: the drawn heights divided by the
// exaggeration, so that colours do not change with it.
float textureMetres(vec2 cell) {
    vec2 f;
    vec4 codes = vec4(gatherQuad(u_heights, v.layer, cell, u_patch_cells, f));
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
vec3 surfaceNormal() {
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

// The slot's mask flags (bit 0: a cell mask; bit 1: a water bitmap; bit 2: all water).
uint maskFlags() { return texelFetch(u_mask_flags, v.layer, 0).r; }

// Whether the cell under this fragment may be drawn. Skirts and walls hang under a border
// sample, whose cell coordinate is C at the far border: the clamp gives them the border cell,
// so they vanish with it.
bool cellDrawable(uint flags) {
    if ((flags & 1u) == 0u)
        return true;
    ivec2 cell = clamp(ivec2(floor(v.cell)), ivec2(0), ivec2(u_patch_cells - 1));
    return texelFetch(u_cell_masks, ivec3(cell, v.layer), 0).r != 0u;
}

// Whether the surface at patch coordinates `cell` is water: the bilinear blend of its four
// samples' water flags is at least 1/2, so that a coastline is as smooth as the heights'
// surface and lies halfway between a water and a land sample, whatever the decoded heights.
// Archives before format 4 store no flags: RIDGE_WATER_FROM_HEIGHT (compiled in per archive)
// applies the old rule, a height at or below 0 m.
bool waterAt(uint flags, vec2 cell, float metres) {
#if RIDGE_WATER_FROM_HEIGHT
    return paletteIsWater(metres);
#else
    if ((flags & 4u) != 0u)
        return true;
    if ((flags & 2u) == 0u)
        return false;
    vec2 f;
    vec4 wet = vec4(gatherQuad(u_water_maps, v.layer, cell, u_patch_cells, f) & uvec4(1u));
    return bilinear(wet, f) >= 0.5;
#endif
}

void main() {
    uint flags = maskFlags();
    if (!cellDrawable(flags))
        discard; // nodata: the terrain ends at the last drawable cell
    if (u_mode == 3) {
        frag_colour = vec4(u_flat_colour, 1.0);
        return;
    }
    // Skirts take the normal and height of the border sample above them (their cell and
    // texcoord are the border's), so that a step between two levels reads as part of the
    // slope, and a skirt hanging through 0 m is not painted as sea.
    float metres = textureMetres(v.cell);
    frag_colour = shadeTerrain(v.position, surfaceNormal(), metres, waterAt(flags, v.cell, metres),
                               v.level, v.factor, v.skirt == 2);
}
