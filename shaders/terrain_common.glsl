// Shared by every stage of the terrain program: per-patch instance data and frame uniforms.
// Positions are camera-relative metres in the terrain frame (lod/terrain_frame.h): on a plane
// x east, y north, z up; on the ellipsoid Earth-centred, Earth-fixed axes. No coordinate of
// Earth scale reaches the GPU: a vertex is its finest-grid offset from the anchor sample
// (the one nearest the camera, integers) mapped through the frame, so floats stay precise
// near the camera wherever it is, and a sample has the same position in every patch.

struct PatchInstance {
    ivec2 origin;       // finest-grid column, row of patch sample (0, 0), relative to u_anchor
    int step;           // finest samples per patch cell: 2^(L − level)
    float morph;        // geomorph: t towards the parent's surface (0 for other schemes)
    int layer;          // texture-array slot of heights, normals and block errors
    int level;          // quadtree level
    float err;          // Err(P), metres
    float skirt_depth;  // metres the skirts hang below the patch border
    vec2 valid_extent;  // level cells of the surface along i, j: ends on the last finest column
                        // and row, possibly inside a cell; >= C: not clipped on that side
    float min_z;        // the patch's heights (and descendants') less the reference height
    float max_z;        // (the camera's z on a plane, its height above the ellipsoid on a globe)
    vec2 valid_start;   // cells along i, j before which the surface is dropped (0 for patches;
                        // a clipmap footprint reaching west or north of the terrain)
    // An arriving patch fading in over the surface drawn before it (lod/arrival_blend.h): the
    // chain of ancestors, nearest first, each with its sample (0, 0) like origin, its finest
    // samples per cell, its slot and its link's weight; fade_weight[0] 0: no fade.
    ivec2 fade_origin[4];
    int fade_step[4];
    int fade_layer[4];
    float fade_weight[4];
    int stand_in;       // 1: stands in for missing descendants; drawn at its full grid
    int pad;
};

layout(std430, binding = 0) readonly buffer PatchInstances { PatchInstance instances[]; };

uniform mat4 u_view_projection; // camera-relative terrain frame -> clip (reverse-Z)
uniform vec2 u_spacing;         // metres per finest sample: (spacing_x, −spacing_y), rows grow south
uniform vec2 u_anchor_offset;   // camera-relative x, y of the anchor sample (the one nearest the camera)
uniform vec2 u_viewport;        // pixels
uniform float u_epsilon;        // ε, pixels
uniform float u_height_scale;   // drawn metres per code: the archive's times u_exaggeration
uniform float u_height_offset;  // k·offset − reference height: drawn metres of code 0 relative to it
uniform float u_exaggeration;   // k: vertical exaggeration (1: true heights); the camera,
                                // instance bounds, Err(P) and skirts are in the k-scaled space
uniform int u_patch_cells;      // C = 2^n
uniform int u_block_cells;      // b
uniform int u_blocks_per_side;  // C / b
uniform int u_block_levels;     // D
uniform int u_cull_blocks;      // 1: drop tessellation blocks outside the view frustum
uniform vec4 u_frustum[6];      // camera-relative planes (n, d), n·p + d >= 0 inside

// The surface: 0 plane, 1 geographic grid on the ellipsoid, 2 projected grid. Compiled in by
// SchemePrograms (a #define per program), not a uniform: llvmpipe executes both sides of a
// branch on a uniform under a mask, so every vertex of the plane paid for the globe's
// trigonometry (2.2x the frame time, docs/PERF.md "Like for like"); the dead side now folds.
#ifndef RIDGE_SURFACE
#error RIDGE_SURFACE is not defined: build terrain programs through SchemePrograms
#endif

// The globe (RIDGE_SURFACE 1): lod::ellipsoidOffset's algebra from the camera's own geodetic
// position (λa, φa, h_ref), formed in double on the CPU (FrameUniforms): offsets are the
// integer sample offset from the anchor sample less the camera's fraction of a sample.
uniform vec4 u_anchor_trig;      // cos φa, sin φa, cos λa, sin λa of the camera
uniform vec2 u_angle_step;       // radians per finest column (Δλ) and row (Δφ)
uniform vec2 u_anchor_fraction;  // the camera's column, row less the anchor sample's, in [−½, ½]
uniform vec4 u_anchor_radii;     // N_a + h_ref, N_a(1 − e²) + h_ref, √(1 − e² sin² φa), e²
uniform float u_semi_major;      // a
uniform int u_wrap_columns;      // columns in 360° when the grid wraps, else 0
uniform ivec2 u_anchor_sample;   // finest column, row of the anchor sample
uniform ivec2 u_pole_rows;       // rows on the north and the south pole, −1 when none
uniform vec3 u_camera_world;     // the camera in ECEF, metres (directions only: ~0.5 m)
uniform float u_polar_ratio;     // 1 / (1 − e²)
uniform float u_bulge_per_rad2;  // (a²/b)/8 (+1%): a chord's sagitta per radian² (chordSag)

// A projected grid on the globe (RIDGE_SURFACE 2): S(c, r), the ellipsoid point under a sample,
// is a bicubic Hermite surface over a lattice of nodes (lod/projected_grid.h), sent relative
// to lattice node L near the camera (ProjectedLattice): per node the residual
// S − S_L − J·(node − L) and its derivatives, J = ∂S/∂(c, r) at L. Near the camera both J·d
// and the residual are small, so floats keep their relative precision there.
uniform int u_lattice_step;      // samples between nodes h (a power of two)
uniform ivec2 u_lattice_nodes;   // nodes along c and r
uniform ivec2 u_lattice_node;    // node L's index
uniform ivec2 u_lattice_delta;   // the anchor sample less node L's sample
uniform vec3 u_lattice_s_c;      // J: ∂S/∂c and ∂S/∂r at L, metres per sample
uniform vec3 u_lattice_s_r;
uniform vec3 u_lattice_base;     // S_L + h_ref·n_L − camera, formed in double
uniform vec3 u_lattice_normal;   // n_L, the ellipsoid's normal at S_L
uniform float u_lattice_m_norm;  // |M·S_L|, M = diag(1, 1, 1/(1 − e²)) (n ∝ M·S)
uniform float u_reference_height; // h_ref: heights reach the GPU relative to it
layout(binding = 9) uniform sampler2DArray u_lattice; // RGBA32F, layers: R, h·R_c, h·R_r, h²·R_cr
#include "projected_lattice.glsl"

layout(binding = 0) uniform usampler2DArray u_heights;     // codes, one layer per patch
layout(binding = 1) uniform sampler2DArray u_normals;      // unit normals, xyz
layout(binding = 2) uniform sampler2DArray u_block_errors; // λ(1..D) metres per block

// Wraps a column offset into [−w/2, w/2) on a grid that goes round the Earth, so that a
// sample and its copy one period away (the antimeridian column) are the same vertex.
int wrapColumnOffset(int dx) {
    if (u_wrap_columns <= 0)
        return dx;
    int w = u_wrap_columns, half_w = w / 2;
    int m = dx + half_w;
    int q = m >= 0 ? m / w : -((w - 1 - m) / w); // floor(m / w) without a negative %
    return m - q * w - half_w;
}

// S(anchor + delta) − S_L on a projected grid: J·d plus the lattice's residual surface.
vec3 projectedSurfaceOffset(ivec2 delta) {
    ivec2 d = delta + u_lattice_delta; // samples from node L
    vec2 t;
    ivec2 node = latticeCell(d, u_lattice_step, u_lattice_node, u_lattice_nodes, t);
    precise vec3 r = latticeSum(u_lattice, node, hermiteWeights(t.x), hermiteWeights(t.y));
    precise vec3 ds = u_lattice_s_c * float(d.x) + u_lattice_s_r * float(d.y) + r;
    return ds;
}

// framePoint on a projected grid: S + (h_ref + dh)·n(S) − camera, every term small near the
// camera. n = M·S / |M·S|; its change from n_L is formed from M·ΔS alone (1/√(1 + q) − 1
// written without cancellation), so h_ref·(n − n_L) keeps its precision too.
vec3 projectedFramePoint(ivec2 delta, float dh, out vec3 up) {
    precise vec3 ds = projectedSurfaceOffset(delta);
    precise vec3 dm = vec3(ds.xy, ds.z * u_polar_ratio) / u_lattice_m_norm;
    precise float q = 2.0 * dot(u_lattice_normal, dm) + dot(dm, dm);
    precise float s = sqrt(1.0 + q);
    precise vec3 dn = (dm - u_lattice_normal * (q / (1.0 + s))) / s;
    up = u_lattice_normal + dn;
    precise vec3 p = u_lattice_base + ds + u_reference_height * dn + dh * up;
    return p;
}

// The point at finest-grid offset `delta` from the anchor sample and `dh` metres above the
// reference height, relative to the camera, and the local up there. On the ellipsoid every
// term of the difference to the camera scales with the offsets (lod/ellipsoid.cpp,
// ellipsoidOffset), so a vertex a kilometre from the camera is exact to a tenth of a
// millimetre.
vec3 framePoint(ivec2 delta, float dh, out vec3 up) {
    if (RIDGE_SURFACE == 0) {
        up = vec3(0.0, 0.0, 1.0);
        precise vec2 xy = vec2(delta) * u_spacing + u_anchor_offset;
        return vec3(xy, dh);
    }
    if (RIDGE_SURFACE == 2)
        return projectedFramePoint(delta, dh, up);
    delta.x = wrapColumnOffset(delta.x);
    precise float dl = (float(delta.x) - u_anchor_fraction.x) * u_angle_step.x;
    precise float dp = (float(delta.y) - u_anchor_fraction.y) * u_angle_step.y;
    float cpa = u_anchor_trig.x, spa = u_anchor_trig.y, cla = u_anchor_trig.z, sla = u_anchor_trig.w;
    precise float hp = sin(0.5 * dp), hl = sin(0.5 * dl);
    precise float d_cos_phi = cpa * (-2.0 * hp * hp) - spa * sin(dp);
    precise float d_sin_phi = spa * (-2.0 * hp * hp) + cpa * sin(dp);
    precise float d_cos_l = cla * (-2.0 * hl * hl) - sla * sin(dl);
    precise float d_sin_l = sla * (-2.0 * hl * hl) + cla * sin(dl);
    precise float cos_phi = cpa + d_cos_phi, sin_phi = spa + d_sin_phi;
    float e2 = u_anchor_radii.w, swa = u_anchor_radii.z;
    precise float d_w = -e2 * d_sin_phi * (sin_phi + spa);
    precise float sw = sqrt(swa * swa + d_w);
    precise float d_n = u_semi_major * -d_w / (sw * swa * (sw + swa));
    float r_a = u_anchor_radii.x, rz_a = u_anchor_radii.y;
    precise float u_a = r_a * cpa;
    int row = u_anchor_sample.y + delta.y;
    precise vec3 d;
    if (row == u_pole_rows.x || row == u_pole_rows.y) {
        // On the axis whatever the longitude: every vertex of a pole row is one point.
        d.xy = -u_a * vec2(cla, sla);
        up = vec3(0.0, 0.0, row == u_pole_rows.x ? 1.0 : -1.0);
    } else {
        precise float d_u = (d_n + dh) * cos_phi + r_a * d_cos_phi;
        d.x = d_u * (cla + d_cos_l) + u_a * d_cos_l;
        d.y = d_u * (sla + d_sin_l) + u_a * d_sin_l;
        up = vec3(cos_phi * (cla + d_cos_l), cos_phi * (sla + d_sin_l), sin_phi);
    }
    d.z = (d_n * (1.0 - e2) + dh) * sin_phi + rz_a * d_sin_phi;
    return d; // the camera is the anchor: d is camera-relative already
}

// The local up at a camera-relative point, from the point alone (for directions: walls,
// shading); +z on a plane.
vec3 worldUp(vec3 position) {
    if (RIDGE_SURFACE == 0)
        return vec3(0.0, 0.0, 1.0);
    vec3 p = position + u_camera_world;
    return normalize(vec3(p.xy, p.z * u_polar_ratio));
}

// Local east, north, up at a camera-relative point (the world axes on a plane).
mat3 localBasis(vec3 position) {
    if (RIDGE_SURFACE == 0)
        return mat3(1.0);
    vec3 up = worldUp(position);
    vec3 east = cross(vec3(0.0, 0.0, 1.0), up);
    east = dot(east, east) > 1e-12 ? normalize(east) : vec3(1.0, 0.0, 0.0); // at a pole
    return mat3(east, cross(up, east), up);
}

// `position` lowered by `depth` metres along the local up (skirts, walls).
vec3 lowered(vec3 position, vec3 up, float depth) {
    if (RIDGE_SURFACE == 0)
        return vec3(position.xy, position.z - depth);
    precise vec3 p = position - depth * up;
    return p;
}

float sampleHeight(int layer, ivec2 sample_ij) {
    precise float z = u_height_offset + u_height_scale * float(texelFetch(u_heights, ivec3(sample_ij, layer), 0).r);
    return z;
}

// Camera-relative position of patch sample (i, j). x, y depend only on the sample's finest-grid
// coordinates (integers relative to the anchor near the camera), never on the patch, so
// vertices on a seam are bit-identical in every patch that has them; heights come from each
// patch's own map (equal on seams between patches of one level).
vec3 samplePosition(PatchInstance p, ivec2 sample_ij, out vec3 up) {
    precise float z = sampleHeight(p.layer, sample_ij);
    return framePoint(p.origin + sample_ij * p.step, z, up);
}
vec3 samplePosition(PatchInstance p, ivec2 sample_ij) {
    vec3 up;
    return samplePosition(p, sample_ij, up);
}

// RIDGE_ARRIVAL_BLEND 1: the programs a streaming renderer draws its fading patches with
// (PatchInstances' fading groups); every other draw compiles it out: llvmpipe runs a branch's
// body under an execution mask whether or not any vertex takes it, which made every vertex of
// a streaming frame pay for the fades (docs/PERF.md, "Arrivals that fade in").
#ifndef RIDGE_ARRIVAL_BLEND
#define RIDGE_ARRIVAL_BLEND 0
#endif

// An ancestor's surface (slot `layer`, sample (0, 0) at finest offset `origin`, `step`
// finest samples per cell) at finest offset `at` from the anchor: linear on its cell
// triangles, split along the diagonal from (i + 1, j) to (i, j + 1) as the patch grid mesh
// (render/patch_grid_mesh.cpp) draws them. Linear on an ancestor's triangles is linear on its
// children's too (their diagonals lie on its), so a chain of fades nests exactly.
float ancestorHeight(int layer, ivec2 origin, int step, ivec2 at) {
    ivec2 q = at - origin; // finest samples into it, >= 0
    ivec2 cell = min(q / step, ivec2(u_patch_cells - 1));
    vec2 f = vec2(q - cell * step) / float(step);
    float h00 = sampleHeight(layer, cell);
    float h11 = sampleHeight(layer, cell + ivec2(1));
    float h10 = sampleHeight(layer, cell + ivec2(1, 0));
    float h01 = sampleHeight(layer, cell + ivec2(0, 1));
    return f.x + f.y <= 1.0 ? h00 + f.x * (h10 - h00) + f.y * (h01 - h00)
                            : h11 + (1.0 - f.x) * (h01 - h11) + (1.0 - f.y) * (h10 - h11);
}

// `z` of patch sample (i, j) faded towards the surface drawn before the patch arrived: its
// nearest ancestor's, itself faded towards the next one's while that fade goes on, and so on
// (S_i = mix(z_Ai, S_(i+1), w_(i+1)), z = mix(z, S_0, w_0)).
float arrivalFade(PatchInstance p, ivec2 sample_ij, float z) {
#if RIDGE_ARRIVAL_BLEND
    if (p.fade_weight[0] > 0.0) {
        ivec2 at = p.origin + sample_ij * p.step;
        int n = 1;
        while (n < 4 && p.fade_weight[n] > 0.0)
            ++n;
        float before = ancestorHeight(p.fade_layer[n - 1], p.fade_origin[n - 1],
                                      p.fade_step[n - 1], at);
        for (int i = n - 2; i >= 0; --i)
            before = mix(ancestorHeight(p.fade_layer[i], p.fade_origin[i], p.fade_step[i], at),
                         before, p.fade_weight[i + 1]);
        z = mix(z, before, p.fade_weight[0]);
    }
#endif
    return z;
}

// The height drawn at patch sample (i, j): its own, faded while the patch arrives. Seams stay
// bit-identical between patches fading alike (siblings that arrived together); others are
// closed by the skirts, which hang by the ancestors' Err too while a patch fades
// (render/patch_instances.cpp).
float drawnHeight(PatchInstance p, ivec2 sample_ij) {
    return arrivalFade(p, sample_ij, sampleHeight(p.layer, sample_ij));
}

// samplePosition with drawnHeight: where the vertex is drawn. The control stages keep
// samplePosition (a patch's tessellation follows its own surface, not the fade).
vec3 drawnPosition(PatchInstance p, ivec2 sample_ij, out vec3 up) {
    precise float z = drawnHeight(p, sample_ij);
    return framePoint(p.origin + sample_ij * p.step, z, up);
}
