#version 450 core
// Sky: horizon haze to zenith blue, from the view ray's elevation.
in vec2 v_ndc;
uniform mat4 u_inverse_view_projection; // clip -> camera-relative terrain frame
uniform vec3 u_horizon_colour;
uniform vec3 u_zenith_colour;
uniform vec3 u_up;      // local up at the camera: +z on a plane, the ellipsoid's normal on a globe
uniform float u_space;  // 0 in the air .. 1 in orbit: how much of the sky is black space
out vec4 frag_colour;
void main() {
    vec4 far_point = u_inverse_view_projection * vec4(v_ndc, 0.5, 1.0);
    vec3 dir = normalize(far_point.xyz / far_point.w);
    float t = clamp(dot(dir, u_up), 0.0, 1.0);
    vec3 sky = mix(u_horizon_colour, u_zenith_colour, pow(t, 0.6));
    frag_colour = vec4(mix(sky, vec3(0.0, 0.0, 0.02), u_space), 1.0);
}
