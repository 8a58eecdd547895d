#version 450 core
// Terrain shading at texture resolution: colour, water and (except geomorph, below) normals
// come from the drawn patch's own height and normal maps at the fragment's patch coordinates,
// not from the mesh, so a coarse mesh still shows every sample of its level (a continent on
// one patch of 184 triangles keeps its coastline). Sun light, the hypsometric palette of
// ridge/core/terrain_palette.h (shaders/palette.glsl, shared with `ridge hillshade`), slope
// shading, distance fog; debug modes for LOD levels and tessellation factors.
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

uniform int u_mode;             // 0 shaded, 1 LOD level colours, 2 tessellation-factor heat map, 3 flat colour
uniform vec3 u_flat_colour;     // mode 3 (wireframe overlay)
uniform vec3 u_sun_direction;   // unit, towards the sun, terrain frame (ECEF on the globe)
uniform vec2 u_height_range;    // camera-relative z of the terrain's min and max
uniform float u_sea_level;      // camera-relative z of 0 m
uniform vec3 u_fog_colour;
uniform float u_fog_density;    // per metre (at sea level on the globe); 0 disables fog
// Globe: the air's scale height (metres; 0 on the plane, whose fog is uniform). The fog then
// follows the air the ray crosses, thinning with altitude (exponential height fog).
uniform float u_fog_scale_height;
uniform int u_block_cells_f;    // b, for the heat map

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
    // Normals are local (east, north, up); on the globe the frame turns with the fragment.
    mat3 basis = localBasis(v.position);
    vec3 n = surfaceNormal();
    if (v.skirt == 2) {
        // A wall is a flat vertical face: its own normal, towards the viewer.
        n = normalize(cross(dFdx(v.position), dFdy(v.position)));
        if (dot(n, v.position) > 0.0)
            n = -n;
        n = transpose(basis) * n;
    }
    float slope = 1.0 - n.z; // 0 flat .. 1 vertical
    vec3 albedo;
    if (u_mode == 1)
        albedo = paletteLevel(v.level);
    else if (u_mode == 2)
        albedo = paletteHeat(log2(max(v.factor, 1.0)) / max(log2(float(u_block_cells_f)), 1.0));
    else {
        float metres = textureMetres(v.cell);
        float min_m = (u_height_range.x - u_sea_level) / u_exaggeration;
        float max_m = (u_height_range.y - u_sea_level) / u_exaggeration;
        bool water = waterAt(v.cell, metres);
        albedo = paletteTerrain(metres, water, min_m, max_m);
        if (!water) {
            float low = max(min_m, 0.0);
            float t = (metres - low) / max(max_m - low, 1e-3);
            if (v.skirt == 2)
                albedo = mix(albedo, vec3(0.36, 0.29, 0.22), 0.6); // walls: earth
            // Steep rock shows through below the snow line.
            albedo = mix(albedo, vec3(0.42, 0.39, 0.36), smoothstep(0.25, 0.55, slope) * (1.0 - step(0.9, t)));
        }
    }
    float sun = max(dot(n, transpose(basis) * u_sun_direction), 0.0);
    float sky = 0.5 + 0.5 * n.z;
    vec3 colour = albedo * (0.78 * sun + 0.30 * sky);
    if (u_fog_density > 0.0) {
        float distance = length(v.position);
        float depth = u_fog_density * distance; // optical depth, uniform air
        if (u_fog_scale_height > 0.0) {
            // Density ∝ exp(−h / H) along the straight ray from the camera (altitude −u_sea_level
            // in drawn metres) to the fragment: τ = β0 L H (e^(−hc/H) − e^(−hf/H)) / (hf − hc),
            // and β0 L e^(−hc/H) for a level ray.
            float H = u_fog_scale_height;
            float hc = -u_sea_level;                            // the camera's, drawn metres
            float hf = textureMetres(v.cell) * u_exaggeration; // the fragment's
            float dh = hf - hc;
            float ec = exp(-hc / H), ef = exp(-hf / H);
            depth = abs(dh) > 1.0 ? u_fog_density * distance * H * (ec - ef) / dh
                                  : u_fog_density * distance * ec;
        }
        colour = mix(colour, u_fog_colour, 1.0 - exp(-depth));
    }
    frag_colour = vec4(pow(colour, vec3(1.0 / 1.1)), 1.0);
}
