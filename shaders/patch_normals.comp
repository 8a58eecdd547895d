#version 450 core
// Normal map of one resident patch, computed on the GPU when it becomes resident (paper,
// "Implementation Details"), from the height-map array. Central differences everywhere: one
// sample beyond the patch's border comes from its resident same-level neighbour's layer, so
// both sides of a seam between patches of one level get the same normals (the renderer
// recomputes a resident neighbour's map when the patch next to it arrives); a neighbour that
// is not resident, or beyond the terrain, is extrapolated linearly (a one-sided difference).
layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = 0) uniform usampler2DArray u_heights;
layout(binding = 0, rgba8_snorm) uniform writeonly image2DArray u_normal_image;

uniform int u_layer;
uniform int u_size;           // samples per side
uniform vec2 u_cell_metres;   // metres per cell along i (east) and j (south)
uniform float u_height_scale; // metres per code
uniform vec2 u_latitude;      // globe: latitude of row 0 and per row, radians; (0, 0) on a plane
uniform ivec4 u_neighbour_layers; // west, east, north, south; −1 when not resident

float code(ivec2 ij, int layer) { return float(texelFetch(u_heights, ivec3(ij, layer), 0).r); }

// Neighbours share the border samples: one step west of our column 0 is the west
// neighbour's column n − 2. Central differences leave at most one coordinate outside.
float codeAt(ivec2 ij) {
    int n = u_size;
    if (ij.x < 0)
        return u_neighbour_layers.x >= 0 ? code(ivec2(n - 2, ij.y), u_neighbour_layers.x)
                                         : 2.0 * code(ivec2(0, ij.y), u_layer) - code(ivec2(1, ij.y), u_layer);
    if (ij.x >= n)
        return u_neighbour_layers.y >= 0 ? code(ivec2(1, ij.y), u_neighbour_layers.y)
                                         : 2.0 * code(ivec2(n - 1, ij.y), u_layer) - code(ivec2(n - 2, ij.y), u_layer);
    if (ij.y < 0)
        return u_neighbour_layers.z >= 0 ? code(ivec2(ij.x, n - 2), u_neighbour_layers.z)
                                         : 2.0 * code(ivec2(ij.x, 0), u_layer) - code(ivec2(ij.x, 1), u_layer);
    if (ij.y >= n)
        return u_neighbour_layers.w >= 0 ? code(ivec2(ij.x, 1), u_neighbour_layers.w)
                                         : 2.0 * code(ivec2(ij.x, n - 1), u_layer) - code(ivec2(ij.x, n - 2), u_layer);
    return code(ij, u_layer);
}

float h(ivec2 ij) { return u_height_scale * codeAt(ij); }

void main() {
    ivec2 ij = ivec2(gl_GlobalInvocationID.xy);
    if (ij.x >= u_size || ij.y >= u_size)
        return;
    // On the globe a cell along a parallel is cos φ of the equator's (a floor keeps the pole
    // rows, where it vanishes, finite: their slope along i is meaningless anyway).
    float cell_i = u_cell_metres.x;
    if (u_latitude.y != 0.0)
        cell_i *= max(cos(u_latitude.x + float(ij.y) * u_latitude.y), 1e-3);
    float dzdi = (h(ij + ivec2(1, 0)) - h(ij - ivec2(1, 0))) / (2.0 * cell_i);
    float dzdj = (h(ij + ivec2(0, 1)) - h(ij - ivec2(0, 1))) / (2.0 * u_cell_metres.y);
    // j grows southwards: dz/dy(north) = −dz/dj.
    vec3 n = normalize(vec3(-dzdi, dzdj, 1.0));
    imageStore(u_normal_image, ivec3(ij, u_layer), vec4(n, 0.0));
}
