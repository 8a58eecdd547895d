// Geomorph helpers (no main): the GLSL twins of include/ridge/lod/geomorph.h and
// include/ridge/lod/hemisphere_normals.h, for the shaders of the `geomorph` renderer.
// shaders/test/geomorph_twin.comp runs them against the C++ (tests/render/geomorph_twin_test.cpp).
//
// Compact vertex (lod::CompactVertex, 8 B; 6 B without the normal), as attributes:
//   bx, by             GL_UNSIGNED_BYTE  ×2, glVertexArrayAttribIFormat  -> uvec2  offset 0
//   height, target     GL_UNSIGNED_SHORT ×2, glVertexArrayAttribIFormat  -> uvec2  offset 2
//   normal_u, normal_v GL_UNSIGNED_BYTE  ×2, glVertexArrayAttribFormat (not normalized)
//                      -> vec2, passed on to the fragment stage for interpolation   offset 6
// and once per block the lod::CompactBlock record as an ivec4 (origin_i, origin_j, patch, b).
//
// Bit-for-bit agreement with the C++ packers where it matters: code -> metres and the morph
// are single correctly rounded IEEE operations in both (GLSL 4.50 requires + - * to be
// correctly rounded), pinned here with `precise` so no driver fuses them into an fma.

#define GEOMORPH_MAP_ORTHOGRAPHIC 0 // lod::HemisphereMap::Orthographic
#define GEOMORPH_MAP_CONCENTRIC 1   // lod::HemisphereMap::Concentric

#ifndef GEOMORPH_NORMALS_BINDING
#define GEOMORPH_NORMALS_BINDING 3 // after terrain_common.glsl's bindings 0..2
#endif

uniform float u_geomorph_height_scale;  // metres per code (GeomorphFrame::scale)
uniform float u_geomorph_height_offset; // metres of code 0 (GeomorphFrame::offset)
uniform vec2 u_geomorph_cell;           // metres per patch cell east, south (cell_x, cell_y), > 0
uniform int u_hemisphere_map;           // GEOMORPH_MAP_*
// lod::buildHemisphereNormalTexture: 256×256 GL_RGBA8, nearest or linear, clamp to edge.
layout(binding = GEOMORPH_NORMALS_BINDING) uniform sampler2D u_hemisphere_normals;

// Patch sample of a compact vertex: the block's origin plus the in-block coordinates.
ivec2 geomorphCompactSample(uvec2 block_coord, ivec4 block) {
    return block.xy + ivec2(block_coord);
}

// Patch-local x (east), y (north) metres of patch sample (i, j): rows grow south.
vec2 geomorphPatchXY(ivec2 sample_ij) {
    precise float x = float(sample_ij.x) * u_geomorph_cell.x;
    precise float y = -(float(sample_ij.y) * u_geomorph_cell.y);
    return vec2(x, y);
}

// lod::geomorphMetres: offset + scale·code.
float geomorphMetres(float code) {
    precise float z = u_geomorph_height_offset + u_geomorph_height_scale * code;
    return z;
}

// lod::morphHeight: mix(h, target, t) spelled out as GLSL defines mix, x·(1 − a) + y·a, so
// that `precise` pins each operation (a built-in mix may be lowered to an fma).
float geomorphMix(float h, float target, float t) {
    precise float keep = 1.0 - t;
    precise float z = h * keep + target * t;
    return z;
}

// Patch-local position of a compact vertex at morph factor t ∈ [0, 1].
// heights = (own code, target code).
vec3 geomorphCompactPosition(uvec2 block_coord, uvec2 heights, ivec4 block, float t) {
    vec2 xy = geomorphPatchXY(geomorphCompactSample(block_coord, block));
    float z = geomorphMix(geomorphMetres(float(heights.x)), geomorphMetres(float(heights.y)), t);
    return vec3(xy, z);
}

// ---- Hemisphere normals -----------------------------------------------------------------

// Square coordinate in (−1, 1) of texel index (u, v) (or of an interpolated index).
vec2 hemisphereSquare(vec2 normal_index) {
    return (2.0 * normal_index + 1.0) / 256.0 - 1.0;
}

// Lift of a disk point straight up (z = sqrt(1 − r²)); outside the disk, the horizon.
vec3 hemisphereLift(vec2 xy) {
    float r2 = dot(xy, xy);
    if (r2 >= 1.0)
        return vec3(xy * inversesqrt(r2), 0.0);
    return vec3(xy, sqrt(1.0 - r2));
}

vec3 hemisphereDecodeOrthographic(vec2 normal_index) {
    return hemisphereLift(hemisphereSquare(normal_index));
}

// Shirley & Chiu's concentric square -> disk map, then the same lift.
vec3 hemisphereDecodeConcentric(vec2 normal_index) {
    vec2 ab = hemisphereSquare(normal_index);
    const float quarter_pi = 0.78539816339744831;
    float r, phi;
    if (ab.x == 0.0 && ab.y == 0.0)
        return vec3(0.0, 0.0, 1.0);
    if (abs(ab.x) > abs(ab.y)) {
        r = ab.x;
        phi = quarter_pi * (ab.y / ab.x);
    } else {
        r = ab.y;
        phi = 2.0 * quarter_pi - quarter_pi * (ab.x / ab.y);
    }
    return hemisphereLift(r * vec2(cos(phi), sin(phi)));
}

// The analytic decoder of `map` (GEOMORPH_MAP_*).
vec3 hemisphereDecode(int map, vec2 normal_index) {
    return map == GEOMORPH_MAP_CONCENTRIC ? hemisphereDecodeConcentric(normal_index)
                                          : hemisphereDecodeOrthographic(normal_index);
}

// The texture lookup (the paper's way): normalize(2·rgb − 1) at the texel centre of a
// (possibly interpolated) index; renormalising also undoes linear filtering's shortening.
vec3 hemisphereNormalLookup(vec2 normal_index) {
    vec3 c = texture(u_hemisphere_normals, (normal_index + 0.5) / 256.0).rgb;
    return normalize(2.0 * c - 1.0);
}
