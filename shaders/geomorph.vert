#version 450 core
// Scheme "geomorph" (Ma, Sun & Song 2013): each selected patch drawn as its regular grid (one
// block of at most 128 cells), every vertex morphed between its own level's height and the
// parent level's surface (the "target height field") by the patch's factor t, so that a patch
// switching level does not jump. The vertex layouts the paper compares:
//   u_layout 0  Standard:   position (morphed on the CPU), normal           locations 0, 2
//   u_layout 1  FloatMorph: position, target height, normal; GPU morph      locations 0, 1, 2
//   u_layout 2  Compact:    block coordinates, height and target codes,
//                           hemisphere-texture normal index; GPU morph      locations 3, 4, 5
// Vertices [0, n²) of a patch are its samples row-major, [n², n² + 4C) copies of its border
// samples in ring order (north row west to east, east column, south row east to west, west
// column) that become the skirt's feet.
#include "terrain_common.glsl"
#include "geomorph_common.glsl"

uniform int u_instance;    // instance record of this draw
uniform int u_base_vertex; // the patch's first vertex (gl_VertexID includes it)
uniform int u_layout;
uniform ivec4 u_geomorph_block; // Compact: the block record (origin_i, origin_j, patch, b)

layout(location = 0) in vec3 a_position;  // patch-local x, y; z: metres of the code scale
layout(location = 1) in float a_target;   // FloatMorph: target height, same frame as z
layout(location = 2) in vec3 a_normal;
layout(location = 3) in uvec2 a_block_coord;
layout(location = 4) in uvec2 a_heights;  // Compact: own and target codes
layout(location = 5) in vec2 a_normal_index;

out Vertex {
    vec3 position;
    vec3 texcoord; // here: the vertex's own normal (see terrain.frag, vertexNormal)
    vec2 cell;
    flat int level;
    flat int layer;     // texture-array slot of the drawn patch (heights, normals)
    flat float factor;
    flat int skirt;
} v;
out Capture {
    vec3 tf_position;
    flat int tf_instance;
    flat int tf_skirt;
} capture;

precise gl_Position;

ivec2 ringSample(int k, int C) {
    if (k < C) return ivec2(k, 0);
    if (k < 2 * C) return ivec2(C, k - C);
    if (k < 3 * C) return ivec2(C - (k - 2 * C), C);
    return ivec2(0, C - (k - 3 * C));
}

void main() {
    PatchInstance p = instances[u_instance];
    int C = u_patch_cells, n = C + 1;
    int local = gl_VertexID - u_base_vertex;
    bool foot = local >= n * n;
    ivec2 sample_ij = foot ? ringSample(local - n * n, C) : ivec2(local % n, local / n);
    precise vec3 position;
    vec3 up = vec3(0.0, 0.0, 1.0);
    if (u_layout == 2) {
        // The sample from the block record and the two bytes: placed exactly as every
        // scheme's samplePosition (bit-identical seams), the height morphed between the codes.
        ivec2 s = geomorphCompactSample(a_block_coord, u_geomorph_block);
        precise float z = arrivalFade(p, s, geomorphMix(geomorphMetres(float(a_heights.x)),
                                                        geomorphMetres(float(a_heights.y)),
                                                        p.morph));
        position = framePoint(p.origin + s * p.step, z, up);
        v.texcoord = vec3(a_normal_index, -1.0);
    } else {
        precise float z = u_layout == 1 ? geomorphMix(a_position.z, a_target, p.morph)
                                        : a_position.z;
        // The CPU's vertices are in metres above code 0; the drawn space is k times that.
        precise float dh = arrivalFade(p, sample_ij, z * u_exaggeration + u_height_offset);
        if (RIDGE_SURFACE == 0) {
            precise vec2 origin = vec2(p.origin) * u_spacing + u_anchor_offset;
            position.xy = origin + a_position.xy;
            position.z = dh;
        } else {
            // The CPU's x, y are plane metres; on the globe the sample places the vertex.
            position = framePoint(p.origin + sample_ij * p.step, dh, up);
        }
        v.texcoord = vec3(a_normal.xy, -2.0 - a_normal.z);
    }
    if (foot)
        position = lowered(position, up, p.skirt_depth);
    v.position = position;
    v.cell = vec2(sample_ij);
    v.level = p.level;
    v.layer = p.layer;
    v.factor = float(u_block_cells);
    v.skirt = foot ? 1 : 0;
    capture.tf_position = position;
    capture.tf_instance = u_instance;
    capture.tf_skirt = foot ? 2 : 0;
    gl_Position = u_view_projection * vec4(position, 1.0);
}
