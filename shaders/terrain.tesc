#version 450 core
// Tessellation control: per-edge factors of one tessellation block, or of one skirt segment
// along the patch border (Yusov & Shevtsov 2011, §5, "Fine-Grain Level of Detail Selection").
#include "terrain_common.glsl"
#include "edge_tessellation.glsl"

layout(vertices = 1) out;

// True when the box [lo, hi] is entirely outside one frustum plane (the p-vertex test).
bool outsideFrustum(vec3 lo, vec3 hi) {
    for (int i = 0; i < 6; ++i) {
        vec4 pl = u_frustum[i];
        vec3 p_vertex = mix(lo, hi, greaterThanEqual(pl.xyz, vec3(0.0)));
        if (dot(pl.xyz, p_vertex) + pl.w < 0.0)
            return true;
    }
    return false;
}

// Drops the primitive: a zero outer level discards it.
void cull() {
    gl_TessLevelOuter[0] = 0.0;
    gl_TessLevelOuter[1] = 0.0;
    gl_TessLevelOuter[2] = 0.0;
    gl_TessLevelOuter[3] = 0.0;
    gl_TessLevelInner[0] = 0.0;
    gl_TessLevelInner[1] = 0.0;
}

// The box around the footprint from sample a to sample b (inclusive) over the patch's height
// range, extended `below` metres down for skirts. On a plane its corners; on the globe the
// corners at both heights, widened by how far the ellipsoid bulges between them.
void blockBox(PatchInstance p, ivec2 a, ivec2 b, float below, out vec3 lo, out vec3 hi) {
    if (RIDGE_SURFACE == 0) {
        vec2 pa = samplePosition(p, a).xy, pb = samplePosition(p, b).xy;
        lo = vec3(min(pa, pb), p.min_z - below);
        hi = vec3(max(pa, pb), p.max_z);
        return;
    }
    lo = vec3(1e30);
    hi = vec3(-1e30);
    vec3 up;
    for (int k = 0; k < 4; ++k) {
        ivec2 s = ivec2((k & 1) != 0 ? b.x : a.x, (k & 2) != 0 ? b.y : a.y);
        ivec2 delta = p.origin + s * p.step;
        vec3 bottom = framePoint(delta, p.min_z - below, up);
        vec3 top = framePoint(delta, p.max_z, up);
        lo = min(lo, min(bottom, top));
        hi = max(hi, max(bottom, top));
    }
    vec2 angles = vec2(b - a) * float(p.step) * u_angle_step;
    vec3 bulge = vec3(u_bulge_per_rad2 * dot(angles, angles));
    lo -= bulge;
    hi += bulge;
}

// Frustum test of that box. Invisible blocks are not tessellated; their neighbours' shared
// edges do not depend on it, so nothing visible can crack.
bool blockInvisible(PatchInstance p, ivec2 a, ivec2 b, float below) {
    if (u_cull_blocks == 0)
        return false;
    vec3 lo, hi;
    blockBox(p, a, b, below, lo, hi);
    return outsideFrustum(lo, hi);
}

in flat int v_primitive[];
in flat int v_instance[];

patch out ivec2 tc_start;   // sample at domain (0, 0)
patch out ivec2 tc_axis;    // skirt: unit sample step along u; block: (0, 0)
patch out int tc_instance;
patch out float tc_factor;  // interior factor, for the heat map

void main() {
    PatchInstance p = instances[v_instance[0]];
    int B = u_blocks_per_side;
    int b = u_block_cells;
    tc_instance = v_instance[0];

    if (v_primitive[0] < B * B) {
        ivec2 sr = ivec2(v_primitive[0] % B, v_primitive[0] / B); // block column s, row r
        ivec2 s0 = sr * b;
        if (blockInvisible(p, s0, s0 + ivec2(b), 0.0)) {
            cull();
            return;
        }
        vec4 own = blockErrors(p, sr);
        // Edges shared by two blocks of the patch take the max of both, so both pick the
        // same factor; border edges have only this block (skirts cover the patch seam).
        vec4 left = sr.x > 0 ? max(own, blockErrors(p, sr - ivec2(1, 0))) : own;
        vec4 top = sr.y > 0 ? max(own, blockErrors(p, sr - ivec2(0, 1))) : own;
        vec4 right = sr.x < B - 1 ? max(own, blockErrors(p, sr + ivec2(1, 0))) : own;
        vec4 bottom = sr.y < B - 1 ? max(own, blockErrors(p, sr + ivec2(0, 1))) : own;
        float f_left = edgeFactor(p, s0, s0 + ivec2(0, b), left);
        float f_top = edgeFactor(p, s0, s0 + ivec2(b, 0), top);
        float f_right = edgeFactor(p, s0 + ivec2(b, 0), s0 + ivec2(b, b), right);
        float f_bottom = edgeFactor(p, s0 + ivec2(0, b), s0 + ivec2(b, b), bottom);
        // GL quad domain: outer[0] u=0, [1] v=0, [2] u=1, [3] v=1; u runs along i, v along j.
        gl_TessLevelOuter[0] = f_left;
        gl_TessLevelOuter[1] = f_top;
        gl_TessLevelOuter[2] = f_right;
        gl_TessLevelOuter[3] = f_bottom;
        float inner;
        if (RIDGE_TESSELLATION_RULE == 1) {
            // The paper: the interior takes the minimum of its edge factors, so an interior
            // nearer the camera than its edge centres (or an edge finer than its neighbours)
            // is drawn coarser than ε allows.
            inner = min(min(f_left, f_top), min(f_right, f_bottom));
        } else {
            // Conservative (lod::interiorFactor): the interior meets ε by its own test. An edge
            // finer than that would put transition triangles at the interior's level, which
            // need the interior's 2λ + Err(P) test; and no finer than the finest edge (edges
            // coarser than the interior cover their transitions by their own test). Only this
            // block reads it: no crack.
            vec3 lo, hi, up;
            blockBox(p, s0, s0 + ivec2(b), 0.0, lo, hi);
            vec3 corners[4] = vec3[4](samplePosition(p, s0), samplePosition(p, s0 + ivec2(b, 0)),
                                      samplePosition(p, s0 + ivec2(0, b)),
                                      samplePosition(p, s0 + ivec2(b)));
            vec3 centre = samplePosition(p, s0 + ivec2(b / 2), up);
            inner = float(b >> interiorSimplification(corners, centre, up, lo, hi, own));
            float finest = max(max(f_left, f_top), max(f_right, f_bottom));
            if (finest > inner) {
                vec4 transition = transitionErrors(own, p.err);
                int d = interiorSimplification(corners, centre, up, lo, hi, transition);
                inner = min(float(b >> d), finest);
            }
        }
        gl_TessLevelInner[0] = inner;
        gl_TessLevelInner[1] = inner;
        tc_start = s0;
        tc_axis = ivec2(0);
        tc_factor = inner;
        return;
    }

    // Skirt segment: side 0 top (j = 0), 1 right (i = C), 2 bottom (j = C), 3 left (i = 0);
    // u runs along +i or +j so that neighbouring segments meet at the same corner samples.
    int k = v_primitive[0] - B * B;
    int side = k / B;
    int t = k % B;
    int C = u_patch_cells;
    ivec2 axis = (side == 0 || side == 2) ? ivec2(1, 0) : ivec2(0, 1);
    ivec2 start = side == 0 ? ivec2(t * b, 0)
                : side == 1 ? ivec2(C, t * b)
                : side == 2 ? ivec2(t * b, C)
                            : ivec2(0, t * b);
    ivec2 block = side == 0 ? ivec2(t, 0)
                : side == 1 ? ivec2(B - 1, t)
                : side == 2 ? ivec2(t, B - 1)
                            : ivec2(0, t);
    if (blockInvisible(p, start, start + axis * b, p.skirt_depth)) {
        cull();
        return;
    }
    // Exactly the block's own border-edge factor: the skirt's top follows its vertices.
    float f = edgeFactor(p, start, start + axis * b, blockErrors(p, block));
    gl_TessLevelOuter[0] = 1.0;
    gl_TessLevelOuter[1] = f;
    gl_TessLevelOuter[2] = 1.0;
    gl_TessLevelOuter[3] = f;
    gl_TessLevelInner[0] = f;
    gl_TessLevelInner[1] = 1.0;
    tc_start = start;
    tc_axis = axis;
    tc_factor = f;
}
