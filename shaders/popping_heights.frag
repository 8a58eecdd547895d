#version 450 core
// The surface's height at one sample (the texel's centre), from the triangle's corners by
// barycentric weights with the CPU's tolerance (render::surfaceHeightsAtSamples). The target
// blends with GL_MAX: where seams between levels cover a sample twice, the upper surface is
// what shows.
flat in vec3 f_corner[3];
layout(location = 0) out float height;

void main() {
    vec3 a = f_corner[0], b = f_corner[1], c = f_corner[2];
    vec2 p = gl_FragCoord.xy;
    float det = (b.y - c.y) * (a.x - c.x) + (c.x - b.x) * (a.y - c.y);
    if (abs(det) < 1e-12)
        discard; // a wall of the clipping shader, or degenerate
    float l0 = ((b.y - c.y) * (p.x - c.x) + (c.x - b.x) * (p.y - c.y)) / det;
    float l1 = ((c.y - a.y) * (p.x - c.x) + (a.x - c.x) * (p.y - c.y)) / det;
    float l2 = 1.0 - l0 - l1;
    // Texel coordinates are exact for samples (integers + 0.5 at stride 1); float rounding of
    // the weights stays far inside this.
    const float tolerance = -1e-5;
    if (l0 < tolerance || l1 < tolerance || l2 < tolerance)
        discard;
    height = l0 * a.z + l1 * b.z + l2 * c.z;
}
