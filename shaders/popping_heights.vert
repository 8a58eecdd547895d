#version 450 core
// A captured surface drawn top-down over a window of finest samples, one texel per `u_stride`
// samples with the texel's centre on its sample: the GPU twin of
// render::surfaceHeightsAtSamples on plane frames. Vertices lie on samples: rounding undoes the
// float error of camera-relative positions, as the CPU rounds them.
layout(location = 0) in vec3 a_position; // camera-relative terrain frame, metres
layout(location = 1) in int a_skirt;     // 0 surface, 1 skirt, 2 a skirt's foot

uniform vec2 u_camera_sample; // the camera's (column, row), fractional
uniform vec2 u_window_first;  // the window's first sample (column, row)
uniform vec2 u_per_metre;     // (1 / spacing_x, −1 / spacing_y)
uniform float u_stride;       // samples per texel
uniform float u_camera_z;     // terrain frame

out vec3 g_texel; // texel coordinates (texel k's centre at k + 0.5) and height
flat out int g_skirt;

void main() {
    vec2 sample_position = round(u_camera_sample + a_position.xy * u_per_metre);
    g_texel = vec3((sample_position - u_window_first) / u_stride + 0.5, a_position.z + u_camera_z);
    g_skirt = a_skirt;
}
