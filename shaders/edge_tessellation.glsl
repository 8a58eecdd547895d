// Fine-grain LOD selection (Yusov & Shevtsov 2011, §5); GPU twin of src/lod/edge_tessellation.cpp.
// Needs terrain_common.glsl.

// Projected length in pixels of the vertical segment of `len` metres centred at `c`.
float projectedVerticalSegment(vec3 c, float len) {
    // precise: both blocks of a shared edge must get the same answer at every call site.
    precise vec4 lo = u_view_projection * vec4(c - vec3(0.0, 0.0, 0.5 * len), 1.0);
    precise vec4 hi = u_view_projection * vec4(c + vec3(0.0, 0.0, 0.5 * len), 1.0);
    if (lo.w <= 1e-6 || hi.w <= 1e-6)
        return 1e30;
    precise float pixels = length((hi.xy / hi.w - lo.xy / lo.w) * 0.5 * u_viewport);
    return pixels;
}

// d = arg max_d proj(e_c ± Λ_e^(d)/2 · e_z) < ε, 0 when no simplification fits.
int edgeSimplification(vec3 centre, vec4 edge_errors) {
    for (int d = u_block_levels; d >= 1; --d)
        if (projectedVerticalSegment(centre, edge_errors[d - 1]) < u_epsilon)
            return d;
    return 0;
}

// Λ^(d) = λ^(d) + Err(P) of block (s, r) of patch `p`.
vec4 blockErrors(PatchInstance p, ivec2 block_sr) {
    return texelFetch(u_block_errors, ivec3(block_sr, p.layer), 0) + vec4(p.err);
}

// Tessellation factor b / 2^d of the block edge from sample a to sample b (both integer,
// b − a along one axis, |b − a| = u_block_cells). `errors` is max Λ of the blocks sharing it.
float edgeFactor(PatchInstance p, ivec2 a, ivec2 b, vec4 errors) {
    vec3 centre = samplePosition(p, (a + b) / 2);
    return float(u_block_cells >> edgeSimplification(centre, errors));
}
