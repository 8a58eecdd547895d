#version 450 core
// Terrain shading: sun light on the GPU-computed normal map, a hypsometric colour ramp with
// slope shading, distance fog; debug modes for LOD levels and tessellation factors.
// From the evaluation shader, or from terrain_clip.geom for patches partly outside the
// valid extent (clipped there exactly, with a wall under the cut).
in Vertex {
    vec3 position;      // camera-relative
    vec3 texcoord;      // normal-map uv and layer
    vec2 cell;          // patch cell coordinates
    flat int level;
    flat float factor;  // interior tessellation factor
    flat int skirt;     // 1 for skirts, 2 for the walls on the clipped border
    flat int layer;     // texture-array slot of the patch
} v;

layout(binding = 1) uniform sampler2DArray u_normals;
// Kept nodata (docs/FORMAT.md, "Validity mask"): per slot, whether it has a cell mask, and the
// mask (1 = drawable) of its C × C cells. Slots without nodata never upload a mask.
layout(binding = 4) uniform usampler2DArray u_cell_masks;
layout(binding = 5) uniform usampler1D u_mask_flags;
uniform int u_patch_cells; // C (terrain_common.glsl)
#include "geomorph_common.glsl"

uniform int u_mode;             // 0 shaded, 1 LOD level colours, 2 tessellation-factor heat map, 3 flat colour
uniform vec3 u_flat_colour;     // mode 3 (wireframe overlay)
uniform vec3 u_sun_direction;   // unit, towards the sun, terrain frame
uniform vec2 u_height_range;    // metres: colour ramp from min to max (camera-relative)
uniform float u_sea_level;      // camera-relative z of 0 m
uniform vec3 u_fog_colour;
uniform float u_fog_density;    // per metre; 0 disables fog
uniform int u_block_cells_f;    // b, for the heat map

out vec4 frag_colour;

vec3 hypsometric(float t) {
    // Lowland green, upland ochre, brown, grey rock, snow.
    const vec3 c0 = vec3(0.20, 0.42, 0.22), c1 = vec3(0.55, 0.58, 0.32), c2 = vec3(0.62, 0.50, 0.34),
               c3 = vec3(0.52, 0.47, 0.44), c4 = vec3(0.95, 0.96, 0.98);
    t = clamp(t, 0.0, 1.0) * 4.0;
    if (t < 1.0) return mix(c0, c1, t);
    if (t < 2.0) return mix(c1, c2, t - 1.0);
    if (t < 3.0) return mix(c2, c3, t - 2.0);
    return mix(c3, c4, smoothstep(0.0, 1.0, t - 3.0));
}

vec3 levelColour(int level) {
    const vec3 palette[8] = vec3[8](vec3(0.90, 0.10, 0.10), vec3(0.95, 0.55, 0.10), vec3(0.95, 0.90, 0.15),
                                    vec3(0.30, 0.80, 0.20), vec3(0.10, 0.70, 0.80), vec3(0.20, 0.35, 0.90),
                                    vec3(0.60, 0.25, 0.85), vec3(0.85, 0.85, 0.85));
    return palette[level % 8];
}

vec3 heat(float t) { // 0 blue (coarse) .. 1 red (full resolution)
    return clamp(vec3(1.5 - abs(4.0 * t - 3.0), 1.5 - abs(4.0 * t - 2.0), 1.5 - abs(4.0 * t - 1.0)), 0.0, 1.0);
}

// The normal map's, or the vertex's own normal where a scheme sends one (geomorph.vert):
// texcoord (u, v, −1) indexes the hemisphere normal texture, (nx, ny, −2 − nz) is a normal.
vec3 surfaceNormal() {
    if (v.texcoord.z >= -0.5)
        return normalize(texture(u_normals, v.texcoord).xyz);
    if (v.texcoord.z > -1.5)
        return normalize(hemisphereNormalLookup(v.texcoord.xy));
    return normalize(vec3(v.texcoord.xy, -2.0 - v.texcoord.z));
}

// Whether the cell under this fragment may be drawn. Skirts and walls hang under a border
// sample, whose cell coordinate is C at the far border: the clamp gives them the border cell,
// so they vanish with it.
bool cellDrawable() {
    if (texelFetch(u_mask_flags, v.layer, 0).r == 0u)
        return true;
    ivec2 cell = clamp(ivec2(floor(v.cell)), ivec2(0), ivec2(u_patch_cells - 1));
    return texelFetch(u_cell_masks, ivec3(cell, v.layer), 0).r != 0u;
}

void main() {
    if (!cellDrawable())
        discard; // nodata: the terrain ends at the last drawable cell
    if (u_mode == 3) {
        frag_colour = vec4(u_flat_colour, 1.0);
        return;
    }
    // Skirts take the normal of the border sample above them, so that a step between two
    // levels reads as part of the slope rather than as a dark line.
    vec3 n = surfaceNormal();
    if (v.skirt == 2) {
        // A wall is a flat vertical face: its own normal, towards the viewer.
        n = normalize(cross(dFdx(v.position), dFdy(v.position)));
        if (dot(n, v.position) > 0.0)
            n = -n;
    }
    float slope = 1.0 - n.z; // 0 flat .. 1 vertical
    vec3 albedo;
    if (u_mode == 1)
        albedo = levelColour(v.level);
    else if (u_mode == 2)
        albedo = heat(log2(max(v.factor, 1.0)) / max(log2(float(u_block_cells_f)), 1.0));
    else {
        float t = (v.position.z - u_height_range.x) / max(u_height_range.y - u_height_range.x, 1e-3);
        albedo = hypsometric(t);
        if (v.skirt == 2)
            albedo = mix(albedo, vec3(0.36, 0.29, 0.22), 0.6); // walls: earth
        albedo = mix(albedo, vec3(0.42, 0.39, 0.36), smoothstep(0.25, 0.55, slope) * (1.0 - step(0.9, t)));
        // DEMs store the sea as flat 0 m: shade it as water (land below sea level keeps its slope).
        if (abs(v.position.z - u_sea_level) < 0.25 && slope < 1e-4)
            albedo = vec3(0.16, 0.30, 0.48);
    }
    float sun = max(dot(n, u_sun_direction), 0.0);
    float sky = 0.5 + 0.5 * n.z;
    vec3 colour = albedo * (0.78 * sun + 0.30 * sky);
    if (u_fog_density > 0.0) {
        float fog = 1.0 - exp(-u_fog_density * length(v.position));
        colour = mix(colour, u_fog_colour, fog);
    }
    frag_colour = vec4(pow(colour, vec3(1.0 / 1.1)), 1.0);
}
