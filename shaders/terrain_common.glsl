// Shared by every stage of the terrain program: per-patch instance data and frame uniforms.
// Positions are camera-relative metres in the terrain frame (x east, y north, z up), so
// floats stay precise however far the camera is from the origin.

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
    float min_z;        // camera-relative bounds of the patch's heights (and descendants')
    float max_z;
};

layout(std430, binding = 0) readonly buffer PatchInstances { PatchInstance instances[]; };

uniform mat4 u_view_projection; // camera-relative terrain frame -> clip (reverse-Z)
uniform vec2 u_spacing;         // metres per finest sample: (spacing_x, −spacing_y), rows grow south
uniform vec2 u_anchor_offset;   // camera-relative x, y of the anchor sample (the one nearest the camera)
uniform vec2 u_viewport;        // pixels
uniform float u_epsilon;        // ε, pixels
uniform float u_height_scale;   // drawn metres per code: the archive's times u_exaggeration
uniform float u_height_offset;  // k·offset − camera z: camera-relative drawn metres of code 0
uniform float u_exaggeration;   // k: vertical exaggeration (1: true heights); the camera,
                                // instance bounds, Err(P) and skirts are in the k-scaled space
uniform int u_patch_cells;      // C = 2^n
uniform int u_block_cells;      // b
uniform int u_blocks_per_side;  // C / b
uniform int u_block_levels;     // D
uniform int u_cull_blocks;      // 1: drop tessellation blocks outside the view frustum
uniform vec4 u_frustum[6];      // camera-relative planes (n, d), n·p + d >= 0 inside

layout(binding = 0) uniform usampler2DArray u_heights;     // codes, one layer per patch
layout(binding = 1) uniform sampler2DArray u_normals;      // unit normals, xyz
layout(binding = 2) uniform sampler2DArray u_block_errors; // λ(1..D) metres per block

float sampleHeight(int layer, ivec2 sample_ij) {
    precise float z = u_height_offset + u_height_scale * float(texelFetch(u_heights, ivec3(sample_ij, layer), 0).r);
    return z;
}

// Camera-relative position of patch sample (i, j). x, y depend only on the sample's finest-grid
// coordinates (integers relative to the anchor near the camera), never on the patch, so
// vertices on a seam are bit-identical in every patch that has them; heights come from each
// patch's own map (equal on seams between patches of one level).
vec3 samplePosition(PatchInstance p, ivec2 sample_ij) {
    precise vec2 xy = vec2(p.origin + sample_ij * p.step) * u_spacing + u_anchor_offset;
    precise float z = sampleHeight(p.layer, sample_ij);
    return vec3(xy, z);
}
