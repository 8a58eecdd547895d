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
// bit 0 of each. Archives before format 4 have none: u_water_from_height applies the old
// rule, a height at or below 0 m.
layout(binding = 6) uniform usampler2DArray u_water_maps;
uniform int u_water_from_height;
#include "geomorph_common.glsl"
#include "palette.glsl"

#include "terrain_shading.glsl"

out vec4 frag_colour;

// Metres above sea level of the patch's height map at patch coordinates `cell`, bilinear
// between its four samples (the codes are integers: no hardware filtering). At a sample this
// is the sample, as `ridge hillshade` sees it. True metres: the drawn heights divided by the
// exaggeration, so that colours do not change with it.
float textureMetres(vec2 cell) {
    int C = u_patch_cells;
    vec2 c = clamp(cell, vec2(0.0), vec2(float(C)));
    ivec2 i0 = min(ivec2(floor(c)), ivec2(C - 1));
    vec2 f = c - vec2(i0);
    float h00 = sampleHeight(v.layer, i0), h10 = sampleHeight(v.layer, i0 + ivec2(1, 0));
    float h01 = sampleHeight(v.layer, i0 + ivec2(0, 1)), h11 = sampleHeight(v.layer, i0 + ivec2(1, 1));
    return (mix(mix(h00, h10, f.x), mix(h01, h11, f.x), f.y) - u_sea_level) / u_exaggeration;
}

// The normal map's, or the vertex's own normal where a scheme sends one (geomorph.vert):
// texcoord (u, v, −1) indexes the hemisphere normal texture, (nx, ny, −2 − nz) is a normal.
// geomorph keeps its vertex normals: it draws every sample of the patch as a vertex, so they
// are at texel resolution already, and they are what its vertex layouts are measured with.
// Normals are of the true surface; the drawn one, z' = k·z, has the normal
// (−k ∂z/∂x, −k ∂z/∂y, 1) ∝ (k·n.x, k·n.y, n.z).
vec3 exaggerated(vec3 n) { return normalize(vec3(n.xy * u_exaggeration, n.z)); }
vec3 surfaceNormal() {
    if (v.texcoord.z >= -0.5)
        return exaggerated(normalize(texture(u_normals, v.texcoord).xyz));
    if (v.texcoord.z > -1.5)
        return exaggerated(normalize(hemisphereNormalLookup(v.texcoord.xy)));
    return exaggerated(normalize(vec3(v.texcoord.xy, -2.0 - v.texcoord.z)));
}

// Whether the cell under this fragment may be drawn. Skirts and walls hang under a border
// sample, whose cell coordinate is C at the far border: the clamp gives them the border cell,
// so they vanish with it.
bool cellDrawable() {
    if ((texelFetch(u_mask_flags, v.layer, 0).r & 1u) == 0u)
        return true;
    ivec2 cell = clamp(ivec2(floor(v.cell)), ivec2(0), ivec2(u_patch_cells - 1));
    return texelFetch(u_cell_masks, ivec3(cell, v.layer), 0).r != 0u;
}

// Whether the surface at patch coordinates `cell` is water: the bilinear blend of its four
// samples' water flags is at least 1/2, so that a coastline is as smooth as the heights'
// surface and lies halfway between a water and a land sample, whatever the decoded heights.
bool waterAt(vec2 cell, float metres) {
    if (u_water_from_height != 0)
        return paletteIsWater(metres);
    uint flags = texelFetch(u_mask_flags, v.layer, 0).r;
    if ((flags & 4u) != 0u)
        return true;
    if ((flags & 2u) == 0u)
        return false;
    int C = u_patch_cells;
    vec2 c = clamp(cell, vec2(0.0), vec2(float(C)));
    ivec2 i0 = min(ivec2(floor(c)), ivec2(C - 1));
    vec2 f = c - vec2(i0);
    float w00 = float(texelFetch(u_water_maps, ivec3(i0, v.layer), 0).r & 1u);
    float w10 = float(texelFetch(u_water_maps, ivec3(i0 + ivec2(1, 0), v.layer), 0).r & 1u);
    float w01 = float(texelFetch(u_water_maps, ivec3(i0 + ivec2(0, 1), v.layer), 0).r & 1u);
    float w11 = float(texelFetch(u_water_maps, ivec3(i0 + ivec2(1, 1), v.layer), 0).r & 1u);
    return mix(mix(w00, w10, f.x), mix(w01, w11, f.x), f.y) >= 0.5;
}

void main() {
    if (!cellDrawable())
        discard; // nodata: the terrain ends at the last drawable cell
    if (u_mode == 3) {
        frag_colour = vec4(u_flat_colour, 1.0);
        return;
    }
    // Skirts take the normal and height of the border sample above them (their cell and
    // texcoord are the border's), so that a step between two levels reads as part of the
    // slope, and a skirt hanging through 0 m is not painted as sea.
    float metres = textureMetres(v.cell);
    frag_colour = shadeTerrain(v.position, surfaceNormal(), metres, waterAt(v.cell, metres),
                               v.level, v.factor, v.skirt == 2);
}
