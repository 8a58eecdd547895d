// Shared by every stage of the terrain program: per-patch instance data and frame uniforms.
// Positions are camera-relative metres in the terrain frame (x east, y north, z up), so
// floats stay precise however far the camera is from the origin.

struct PatchInstance {
    vec2 origin;        // camera-relative x, y of patch sample (0, 0)
    vec2 cell;          // metres per patch cell along +i (east) and +j (rows grow south: y < 0)
    int layer;          // texture-array slot of heights, normals and block errors
    int level;          // quadtree level
    float err;          // Err(P), metres
    float skirt_bottom; // camera-relative z of the skirts' lower edge
    ivec2 valid_cells;  // cells of the patch inside the valid extent along i, j
    int pad0;
    int pad1;
};

layout(std430, binding = 0) readonly buffer PatchInstances { PatchInstance instances[]; };

uniform mat4 u_view_projection; // camera-relative terrain frame -> clip (reverse-Z)
uniform vec2 u_viewport;        // pixels
uniform float u_epsilon;        // ε, pixels
uniform float u_height_scale;   // metres per code
uniform float u_height_offset;  // offset − camera z: camera-relative metres of code 0
uniform int u_patch_cells;      // C = 2^n
uniform int u_block_cells;      // b
uniform int u_blocks_per_side;  // C / b
uniform int u_block_levels;     // D

layout(binding = 0) uniform usampler2DArray u_heights;     // codes, one layer per patch
layout(binding = 1) uniform sampler2DArray u_normals;      // unit normals, xyz
layout(binding = 2) uniform sampler2DArray u_block_errors; // λ(1..D) metres per block

float sampleHeight(int layer, ivec2 sample_ij) {
    return u_height_offset + u_height_scale * float(texelFetch(u_heights, ivec3(sample_ij, layer), 0).r);
}

// Camera-relative position of patch sample (i, j). Every stage that places a vertex on a
// sample calls this with integer inputs, so shared vertices are bit-identical.
vec3 samplePosition(PatchInstance p, ivec2 sample_ij) {
    return vec3(p.origin + vec2(sample_ij) * p.cell, sampleHeight(p.layer, sample_ij));
}
