#version 450 core
// The popping metric's reduction (render::measurePopping on the GPU, plane frames): for each
// sample of this frame's window that the previous frame's window holds too and both surfaces
// cover, the distance in pixels between the projections of its two heights; the largest
// distance, the largest height change and the samples counted, by atomics (non-negative float
// bits order as uints). One invocation per texel of this frame's window.
layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = 0) uniform sampler2D u_before; // R32F heights; -FLT_MAX: not covered
layout(binding = 1) uniform sampler2D u_after;
layout(std430, binding = 2) buffer Result {
    uint samples;
    uint max_px_bits;
    uint max_metres_bits;
};

uniform ivec2 u_texels;         // this frame's window, texels
uniform ivec2 u_first;          // its first sample (column, row)
uniform int u_stride;           // its samples per texel
uniform ivec2 u_before_texels;  // the previous frame's window likewise
uniform ivec2 u_before_first;
uniform int u_before_stride;
uniform vec2 u_origin;          // this window's first sample less the camera, metres (x, y)
uniform vec2 u_texel_metres;    // one texel's step: (stride · spacing_x, −stride · spacing_y)
uniform float u_camera_z;
uniform mat4 u_view_projection; // lod::Camera::viewProjection (camera-relative, GL depth)
uniform vec3 u_forward;
uniform float u_near;
uniform vec2 u_viewport;

// lod::Camera::project of a clip-space point.
bool toPixel(vec4 clip, out vec2 pixel) {
    if (clip.w <= u_near * 0.5)
        return false;
    pixel = vec2((clip.x / clip.w * 0.5 + 0.5) * u_viewport.x,
                 (0.5 - clip.y / clip.w * 0.5) * u_viewport.y);
    return true;
}

bool inViewport(vec2 pixel) {
    return all(greaterThanEqual(pixel, vec2(0.0))) && all(lessThanEqual(pixel, u_viewport));
}

// The workgroup's figures, reduced here first: one global atomic each per group.
shared uint group_samples, group_max_px_bits, group_max_metres_bits;

// This invocation's sample, when both surfaces cover it and it is in view.
bool measure(out float px, out float metres) {
    ivec2 t = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(t, u_texels)))
        return false;
    // The same sample in the previous window: on its lattice and inside it.
    ivec2 offset = u_first + t * u_stride - u_before_first;
    ivec2 tb = offset / u_before_stride;
    if (any(lessThan(offset, ivec2(0))) || any(notEqual(tb * u_before_stride, offset)) ||
        any(greaterThanEqual(tb, u_before_texels)))
        return false;
    float a = texelFetch(u_before, tb, 0).r, b = texelFetch(u_after, t, 0).r;
    if (a < -1e38 || b < -1e38)
        return false;
    vec2 xy = u_origin + vec2(t) * u_texel_metres;
    vec3 pa = vec3(xy, a - u_camera_z);
    // The two points differ in z alone: one product, and the second clip point from the first.
    vec4 clip_a = u_view_projection * vec4(pa, 1.0);
    vec4 clip_b = clip_a + (b - a) * u_view_projection[2];
    vec2 xa, xb;
    if (!toPixel(clip_a, xa) || !toPixel(clip_b, xb))
        return false;
    if (!(inViewport(xa) || inViewport(xb)) || dot(pa, u_forward) < u_near)
        return false;
    px = length(xa - xb);
    metres = abs(a - b);
    return true;
}

void main() {
    if (gl_LocalInvocationIndex == 0) {
        group_samples = 0u;
        group_max_px_bits = 0u;
        group_max_metres_bits = 0u;
    }
    barrier();
    float px, metres;
    if (measure(px, metres)) {
        atomicAdd(group_samples, 1u);
        atomicMax(group_max_px_bits, floatBitsToUint(px));
        atomicMax(group_max_metres_bits, floatBitsToUint(metres));
    }
    barrier();
    if (gl_LocalInvocationIndex == 0 && group_samples > 0u) {
        atomicAdd(samples, group_samples);
        atomicMax(max_px_bits, group_max_px_bits);
        atomicMax(max_metres_bits, group_max_metres_bits);
    }
}
