// A projected grid's lattice (lod/projected_grid.h): S(c, r), the ellipsoid point under
// finest sample (c, r), as a bicubic Hermite surface over nodes every h samples. A lattice
// texture holds per node four RGBA32F layers: a value, its derivatives along c and r times h,
// and its cross derivative times h² (ProjectedLattice: relative to a node near the camera;
// the normal maps' copy: absolute). Shared by terrain_common.glsl and patch_normals.comp.

// floor(a / b) for b > 0 without a negative %.
int floorDiv(int a, int b) { return a >= 0 ? a / b : -((b - 1 - a) / b); }

// The cubic Hermite basis on [0, 1]: weights of the values at 0 and 1 and of the derivatives
// (times the cell's length) there (lod::hermiteWeights), and their d/du.
vec4 hermiteWeights(float u) {
    float u2 = u * u, u3 = u2 * u;
    return vec4(2.0 * u3 - 3.0 * u2 + 1.0, -2.0 * u3 + 3.0 * u2, u3 - 2.0 * u2 + u, u3 - u2);
}
vec4 hermiteSlopes(float u) {
    float u2 = u * u;
    return vec4(6.0 * u2 - 6.0 * u, -6.0 * u2 + 6.0 * u, 3.0 * u2 - 4.0 * u + 1.0, 3.0 * u2 - 2.0 * u);
}

// The lattice cell (its first node, clamped to the lattice) of a sample `d` samples from
// node `origin`'s, and the fractions t in it (outside [0, 1] beyond the lattice).
ivec2 latticeCell(ivec2 d, int h, ivec2 origin, ivec2 nodes, out vec2 t) {
    ivec2 node = clamp(origin + ivec2(floorDiv(d.x, h), floorDiv(d.y, h)), ivec2(0), nodes - 2);
    t = vec2(d - (node - origin) * h) / float(h);
    return node;
}

// Σ over the cell's four nodes of the tensor-product weights wu ⊗ wv times the layers.
vec3 latticeSum(sampler2DArray lattice, ivec2 node, vec4 wu, vec4 wv) {
    precise vec3 s = vec3(0.0);
    for (int b = 0; b < 2; ++b)
        for (int a = 0; a < 2; ++a) {
            ivec2 n = node + ivec2(a, b);
            s += wu[a] * wv[b] * texelFetch(lattice, ivec3(n, 0), 0).xyz +
                 wu[2 + a] * wv[b] * texelFetch(lattice, ivec3(n, 1), 0).xyz +
                 wu[a] * wv[2 + b] * texelFetch(lattice, ivec3(n, 2), 0).xyz +
                 wu[2 + a] * wv[2 + b] * texelFetch(lattice, ivec3(n, 3), 0).xyz;
        }
    return s;
}
