// Bilinear reads of integer per-sample maps (heights, water flags) at fractional patch
// coordinates, as one textureGather: one texture operation on llvmpipe where four texelFetch
// were four (integer textures cannot be filtered by the hardware). terrain.frag's colour and
// water at texture resolution; tests/render/texel_quad_twin_test.cpp checks it against a CPU
// bilinear of the same texels.

// The 2 × 2 samples of `layer` of an n × n map (n = cells + 1) around coordinates `cell`
// (clamped to [0, cells]), and the bilinear weights `f` between them. Gather order: x (i0,
// j0 + 1), y (i0 + 1, j0 + 1), z (i0 + 1, j0), w (i0, j0). The point (i0 + 1, j0 + 1) / n is
// the corner the four texels share, so the gather picks exactly them whatever the filter.
uvec4 gatherQuad(usampler2DArray map, int layer, vec2 cell, int cells, out vec2 f) {
    vec2 c = clamp(cell, vec2(0.0), vec2(float(cells)));
    ivec2 i0 = min(ivec2(floor(c)), ivec2(cells - 1));
    f = c - vec2(i0);
    return textureGather(map, vec3(vec2(i0 + 1) / float(cells + 1), float(layer)), 0);
}

// Bilinear blend of a gathered quad (gatherQuad's order) with weights `f`: (i0, j0) at f = 0.
float bilinear(vec4 q, vec2 f) { return mix(mix(q.w, q.z, f.x), mix(q.x, q.y, f.x), f.y); }
