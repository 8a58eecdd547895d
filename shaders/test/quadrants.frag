#version 450 core
// Red marks the right half, green the top half (GL window coordinates, origin bottom-left);
// blue is constant. A readback that is not flipped to top-row-first shows green at the bottom.
#include "test/common.glsl"

uniform vec2 u_size; // render target size, pixels
uniform float u_depth_top;    // gl_FragDepth written in the top half
uniform float u_depth_bottom; // ... and in the bottom half
layout(location = 0) out vec4 colour;

void main()
{
    const float top = pastMiddle(gl_FragCoord.y, u_size.y);
    colour = vec4(pastMiddle(gl_FragCoord.x, u_size.x), top, 0.25, 1.0);
    gl_FragDepth = mix(u_depth_bottom, u_depth_top, top);
}
