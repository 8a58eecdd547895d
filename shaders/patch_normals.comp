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
// A projected grid on the globe (u_projected 1): normals in east, north, up, from the grid's
// tangents ∂S/∂c, ∂S/∂r at each sample, evaluated on the lattice (absolute: float S is good
// to ~0.5 m, its tangents to a few 1e-4 rad) and taken in the local east and north there
// (the meridian convergence, which turns through a whole circle round a pole in the grid).
uniform int u_projected;
uniform ivec2 u_patch_origin;  // finest column, row of the patch's sample (0, 0)
uniform int u_patch_step;      // finest samples per cell
uniform ivec2 u_lattice_first; // finest column, row of lattice node (0, 0)
uniform int u_lattice_step;    // finest samples between nodes h
uniform ivec2 u_lattice_nodes; // nodes along c and r
uniform float u_polar_ratio;   // 1 / (1 − e²)
layout(binding = 10) uniform sampler2DArray u_lattice; // S, h·S_c, h·S_r, h²·S_cr

#include "projected_lattice.glsl"

// East and north metres of one finest column (xy) and one row (zw) at finest sample `cr`.
vec4 gridAxes(ivec2 cr) {
    vec2 t;
    ivec2 node = latticeCell(cr - u_lattice_first, u_lattice_step, ivec2(0), u_lattice_nodes, t);
    vec4 wu = hermiteWeights(t.x), wv = hermiteWeights(t.y);
    vec3 s = latticeSum(u_lattice, node, wu, wv);
    float node_step = float(u_lattice_step);
    vec3 s_c = latticeSum(u_lattice, node, hermiteSlopes(t.x), wv) / node_step;
    vec3 s_r = latticeSum(u_lattice, node, wu, hermiteSlopes(t.y)) / node_step;
    vec3 up = normalize(vec3(s.xy, s.z * u_polar_ratio));
    vec3 east = vec3(-up.y, up.x, 0.0); // z × up
    east = dot(east, east) > 1e-20 ? normalize(east) : vec3(1.0, 0.0, 0.0); // at a pole
    vec3 north = cross(up, east);
    return vec4(dot(s_c, east), dot(s_c, north), dot(s_r, east), dot(s_r, north));
}

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
    if (u_projected != 0) {
        // Tangents along i and j in east, north, up; their cross product points down (j runs
        // against north on a north-up grid), hence the flip to the upper side.
        vec4 axes = gridAxes(u_patch_origin + ij * u_patch_step);
        float step = float(u_patch_step);
        vec3 ti = vec3(axes.xy * step, 0.5 * (h(ij + ivec2(1, 0)) - h(ij - ivec2(1, 0))));
        vec3 tj = vec3(axes.zw * step, 0.5 * (h(ij + ivec2(0, 1)) - h(ij - ivec2(0, 1))));
        vec3 n = normalize(cross(ti, tj));
        imageStore(u_normal_image, ivec3(ij, u_layer), vec4(n.z < 0.0 ? -n : n, 0.0));
        return;
    }
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
