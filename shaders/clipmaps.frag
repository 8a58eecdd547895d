#version 450 core
// Scheme clipmaps' fragment stage: shading at the level textures' resolution. Height, water
// and the normal come from the fragment's level texture (toroidal), not from the patch
// layers other schemes read: a clipmap draws levels, not patches. Normals are per sample,
// central differences of the samples' positions (one-sided on the window's border, as the
// thesis §3.5.3), bilinear between the cell's four samples; in the transition region they
// and the height blend into the coarser level's as the geometry does (α from clipmaps.vert).
// Kept nodata: a cell whose flag says so is not drawn (the flags were filled from the
// patches' cell masks). The colour is terrain_shading.glsl's, as for every scheme.
in Vertex {
    vec3 position; // camera-relative
    vec3 texcoord; // the window's cells (x, y) and α
    vec2 cell;
    flat int level;
    flat int layer; // the level (texture layer)
    flat float factor;
    flat int skirt; // 2: a wall under the clipped border
} v;

#include "terrain_common.glsl"
#include "palette.glsl"
#include "terrain_shading.glsl"

const int kMaxLevels = 24; // lod::ClipmapSettings::kMaxLevels
layout(binding = 11) uniform usampler2DArray u_levels; // RG16UI: code, flags
uniform int u_texture_size;                // N
uniform int u_window;                      // n
uniform ivec2 u_level_texel[kMaxLevels];   // texel of each window's sample (0, 0)
uniform ivec2 u_level_origin[kMaxLevels];  // finest offset of each window's (0, 0) from the anchor
uniform int u_level_step[kMaxLevels];      // finest samples per cell of each level
uniform vec2 u_in_coarser[kMaxLevels];     // each window's (0, 0) in the coarser window's cells
// RIDGE_WATER_FROM_HEIGHT (compiled in per archive): 1 for archives before format 4, whose
// water is the palette's old rule, a height at or below 0 m.
#ifndef RIDGE_WATER_FROM_HEIGHT
#error RIDGE_WATER_FROM_HEIGHT is not defined: build terrain programs through SchemePrograms
#endif

out vec4 frag_colour;

uvec2 texelAt(int layer, ivec2 w) {
    w = clamp(w, ivec2(0), ivec2(u_window - 1));
    return texelFetch(u_levels, ivec3((u_level_texel[layer] + w) & ivec2(u_texture_size - 1), layer), 0).rg;
}
float heightAt(int layer, ivec2 w) {
    return u_height_offset + u_height_scale * float(texelAt(layer, w).r);
}
// Sample w of a level where the vertex shader puts it (camera-relative, the terrain frame).
vec3 samplePoint(int layer, ivec2 w) {
    w = clamp(w, ivec2(0), ivec2(u_window - 1));
    vec3 up;
    return framePoint(u_level_origin[layer] + w * u_level_step[layer], heightAt(layer, w), up);
}
// The surface normal at sample w (terrain frame): central differences of the samples' own
// positions, so it holds on a plane, on the ellipsoid and on a projected grid alike.
vec3 sampleNormal(int layer, ivec2 w) {
    vec3 along_x = samplePoint(layer, w + ivec2(1, 0)) - samplePoint(layer, w - ivec2(1, 0));
    vec3 along_y = samplePoint(layer, w + ivec2(0, 1)) - samplePoint(layer, w - ivec2(0, 1));
    vec3 up = worldUp(samplePoint(layer, w));
    // On a pole row every sample is one point: no east-west tangent, and the normal of the
    // cap there is the local up (a zero cross product would shade it NaN, black).
    if (dot(along_x, along_x) <= 1e-12 * dot(along_y, along_y))
        return up;
    vec3 n = cross(along_y, along_x); // columns east, rows south: up
    return dot(n, up) < 0.0 ? -n : n;
}
// Height (drawn metres relative to the reference), normal (terrain frame) and water at
// window cells `w`, bilinear between the cell's samples.
void surfaceAt(int layer, vec2 w, out float z, out vec3 n, out float water) {
    vec2 c = clamp(w, vec2(0.0), vec2(float(u_window - 1)));
    ivec2 i0 = min(ivec2(floor(c)), ivec2(u_window - 2));
    vec2 f = c - vec2(i0);
    float h00 = heightAt(layer, i0), h10 = heightAt(layer, i0 + ivec2(1, 0));
    float h01 = heightAt(layer, i0 + ivec2(0, 1)), h11 = heightAt(layer, i0 + ivec2(1, 1));
    z = mix(mix(h00, h10, f.x), mix(h01, h11, f.x), f.y);
    n = mix(mix(normalize(sampleNormal(layer, i0)), normalize(sampleNormal(layer, i0 + ivec2(1, 0))), f.x),
            mix(normalize(sampleNormal(layer, i0 + ivec2(0, 1))), normalize(sampleNormal(layer, i0 + ivec2(1, 1))), f.x), f.y);
    float w00 = float(texelAt(layer, i0).g >> 1), w10 = float(texelAt(layer, i0 + ivec2(1, 0)).g >> 1);
    float w01 = float(texelAt(layer, i0 + ivec2(0, 1)).g >> 1), w11 = float(texelAt(layer, i0 + ivec2(1, 1)).g >> 1);
    water = mix(mix(w00, w10, f.x), mix(w01, w11, f.x), f.y);
}

void main() {
    ivec2 cell = clamp(ivec2(floor(v.texcoord.xy)), ivec2(0), ivec2(u_window - 2));
    if ((texelAt(v.layer, cell).g & 1u) == 0u)
        discard; // kept nodata: the terrain ends at the last drawable cell
    if (u_mode == 3) {
        frag_colour = vec4(u_flat_colour, 1.0);
        return;
    }
    float z, water;
    vec3 n;
    surfaceAt(v.layer, v.texcoord.xy, z, n, water);
    float alpha = v.texcoord.z;
    if (alpha > 0.0 && v.layer > 0) {
        float zc, wc;
        vec3 nc;
        surfaceAt(v.layer - 1, u_in_coarser[v.layer] + 0.5 * v.texcoord.xy, zc, nc, wc);
        z = mix(z, zc, alpha);
        n = mix(n, nc, alpha);
        water = mix(water, wc, alpha);
    }
    n = transpose(localBasis(v.position)) * normalize(n); // local east, north, up
    float metres = (z - u_sea_level) / u_exaggeration;
    bool wet = RIDGE_WATER_FROM_HEIGHT != 0 ? paletteIsWater(metres) : water >= 0.5;
    frag_colour = shadeTerrain(v.position, n, metres, wet, v.level, v.factor,
                               v.skirt == 2);
}
