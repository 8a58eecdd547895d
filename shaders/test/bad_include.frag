#version 450 core
// The error is in the included file; its messages must name test/broken.glsl.
#include "test/broken.glsl"
layout(location = 0) out vec4 colour;
void main()
{
    colour = brokenColour();
}
