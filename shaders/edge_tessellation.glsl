// Fine-grain LOD selection (Yusov & Shevtsov 2011, §5); GPU twin of src/lod/edge_tessellation.cpp.
// Needs terrain_common.glsl.

// lod::TessellationRule, compiled in like RIDGE_SURFACE (one program per rule): 0 conservative,
// 1 the paper's. As a uniform, llvmpipe ran the conservative rule's extra projections under a
// mask in the paper rule's draws too.
#ifndef RIDGE_TESSELLATION_RULE
#error RIDGE_TESSELLATION_RULE is not defined: build the tessellation programs through SchemePrograms
#endif
// LOD is decided for the LOD camera (TerrainRenderer::draw's lod_camera; usually the camera
// drawn from): camera-relative positions → its clip space, and its position relative to
// the drawn camera.
uniform mat4 u_lod_view_projection;
uniform vec3 u_lod_camera;

// Projected length in pixels of the segment of `len` metres along the local up `up` (the
// height's direction: +z on a plane) centred at `c`.
float projectedVerticalSegment(vec3 c, vec3 up, float len) {
    // precise: both blocks of a shared edge must get the same answer at every call site.
    precise vec4 lo = u_lod_view_projection * vec4(c - up * (0.5 * len), 1.0);
    precise vec4 hi = u_lod_view_projection * vec4(c + up * (0.5 * len), 1.0);
    if (lo.w <= 1e-6 || hi.w <= 1e-6)
        return 1e30;
    precise float pixels = length((hi.xy / hi.w - lo.xy / lo.w) * 0.5 * u_viewport);
    return pixels;
}

// d = arg max_d proj(e_c ± Λ_e^(d)/2 · e_z) < ε, 0 when no simplification fits; e_z is the
// local up at the point (`up`).
int edgeSimplification(vec3 centre, vec3 up, vec4 edge_errors) {
    for (int d = u_block_levels; d >= 1; --d)
        if (projectedVerticalSegment(centre, up, edge_errors[d - 1]) < u_epsilon)
            return d;
    return 0;
}

// The point of segment [a, b] nearest the LOD camera (the origin when it is the camera drawn
// from, positions being camera-relative).
vec3 nearestPointOfSegment(vec3 a, vec3 b) {
    precise vec3 ab = b - a;
    precise vec3 to_camera = u_lod_camera - a;
    precise float t = clamp(dot(to_camera, ab) / max(dot(ab, ab), 1e-30), 0.0, 1.0);
    precise vec3 q = a + t * ab;
    return q;
}

// 2λ^(d) + Err(P) = 2Λ^(d) − Err(P): what bounds a tessellator transition triangle whose
// coarser side is at d (lod::transitionErrors; the argument is in ridge/lod/edge_tessellation.h).
vec4 transitionErrors(vec4 errors, float patch_error) {
    precise vec4 e = 2.0 * errors - vec4(patch_error);
    return e;
}

// d of the edge from `a` to `b` with centre sample `centre`. The paper projects Λ_e^(d) at the
// centre only, but the edge's near end projects larger (up to 2× for an edge as long as it is
// far), and that is where its error shows: the conservative rule takes the most demanding of
// the endpoints, the centre sample and the edge's point nearest the camera. And it projects
// transitionErrors: a sample under a transition triangle between this edge and a finer
// interior is within 2λ_e^(d) + Err(P) of the source (one Λ^(d) did 1.14 ε on the renderer
// test's cameras). Only the edge's own samples and the patch's Err(P) enter, so both blocks of
// a shared edge (and a block and its skirt) agree.
// `up` is the local up at the edge's centre sample (the edge is short against the Earth's
// radius: its direction differs by less than the segment's own rounding elsewhere).
int edgeSimplification(vec3 a, vec3 centre, vec3 b, vec3 up, vec4 edge_errors, float patch_error) {
    if (RIDGE_TESSELLATION_RULE == 1)
        return edgeSimplification(centre, up, edge_errors);
    vec4 e = transitionErrors(edge_errors, patch_error);
    int d = min(edgeSimplification(a, up, e), edgeSimplification(b, up, e));
    d = min(d, edgeSimplification(centre, up, e));
    return min(d, edgeSimplification(nearestPointOfSegment(a, b), up, e));
}

// Conservative d of a block's interior with its own Λ^(d): the most demanding of its corners,
// its centre sample and the point of its footprint box [lo, hi] nearest the camera, which is
// nearer than any sample of the block (a vertical segment projects longer the nearer it is,
// except seen end-on from above, where it is short anyway).
int interiorSimplification(vec3 corners[4], vec3 centre, vec3 up, vec3 lo, vec3 hi,
                           vec4 errors) {
    int d = edgeSimplification(clamp(u_lod_camera, lo, hi), up, errors);
    d = min(d, edgeSimplification(centre, up, errors));
    for (int k = 0; k < 4; ++k)
        d = min(d, edgeSimplification(corners[k], up, errors));
    return d;
}

// Λ^(d) = λ^(d) + Err(P) of block (s, r) of patch `p`, in the drawn (exaggerated) space: λ is
// stored in metres, p.err is exaggerated already.
// On the globe Λ^(d) also holds the sagitta of an edge 2^d cells long (TerrainFrame::chordSag):
// the simplified triangles' straight edges pass below the curved surface.
vec4 blockErrors(PatchInstance p, ivec2 block_sr) {
    vec4 lambda = texelFetch(u_block_errors, ivec3(block_sr, p.layer), 0) * u_exaggeration + vec4(p.err);
    if (RIDGE_SURFACE == 0)
        return lambda;
    vec2 cell = float(p.step) * u_angle_step;
    return lambda + vec4(4.0, 16.0, 64.0, 256.0) * (u_bulge_per_rad2 * dot(cell, cell));
}

// Tessellation factor b / 2^d of the block edge from sample a to sample b (both integer,
// b − a along one axis, |b − a| = u_block_cells). `errors` is max Λ of the blocks sharing it.
float edgeFactor(PatchInstance p, ivec2 a, ivec2 b, vec4 errors) {
    vec3 up;
    vec3 centre = samplePosition(p, (a + b) / 2, up);
    return float(u_block_cells >> edgeSimplification(samplePosition(p, a), centre,
                                                     samplePosition(p, b), up, errors, p.err));
}
