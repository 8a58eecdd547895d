#version 450 core
// The window of finest samples a captured surface spans, for the popping metric on the GPU
// (render::surfaceHeightsAtSamples' window, plane frames): min and max column and row over the
// surface's vertices (skirt vertices left out), rounded to samples as the CPU rounds them. A
// grid-stride loop: a frame may capture more vertices than one dispatch has invocations.
layout(local_size_x = 256) in;

struct CapturedVertex { // render::CapturedVertex, as transform feedback wrote it
    float x, y, z;      // camera-relative terrain frame, metres
    int instance;
    int skirt;
};
layout(std430, binding = 0) readonly buffer Vertices { CapturedVertex vertices[]; };
layout(std430, binding = 1) buffer Window { int lo_x, lo_y, hi_x, hi_y; };

uniform uint u_count;         // vertices
uniform vec2 u_camera_sample; // the camera's (column, row), fractional
uniform vec2 u_per_metre;     // (1 / spacing_x, −1 / spacing_y)

void main() {
    uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    for (uint i = gl_GlobalInvocationID.x; i < u_count; i += stride) {
        CapturedVertex v = vertices[i];
        if (v.skirt != 0)
            continue;
        ivec2 s = ivec2(round(u_camera_sample + vec2(v.x, v.y) * u_per_metre));
        atomicMin(lo_x, s.x);
        atomicMin(lo_y, s.y);
        atomicMax(hi_x, s.x);
        atomicMax(hi_y, s.y);
    }
}
