#version 450 core
// Evaluates shaders/palette.glsl at a batch of inputs so that tests can compare it with
// ridge::palette (its C++ twin): per case (metres, min, max, heat t) the terrain colour (water
// by the height rule, and for every third case by a flag whatever the height: a lake), the
// heat colour and the colour of level int(metres).
#include "palette.glsl"

layout(local_size_x = 64) in;

layout(std430, binding = 1) readonly buffer Cases { vec4 cases[]; };
layout(std430, binding = 2) writeonly buffer Results { vec4 colours[]; };

uniform int u_case_count;

void main() {
    int i = int(gl_GlobalInvocationID.x);
    if (i >= u_case_count)
        return;
    vec4 c = cases[i];
    bool water = paletteIsWater(c.x) || i % 3 == 0;
    colours[3 * i] = vec4(paletteTerrain(c.x, water, c.y, c.z), paletteIsWater(c.x) ? 1.0 : 0.0);
    colours[3 * i + 1] = vec4(paletteHeat(c.w), 0.0);
    colours[3 * i + 2] = vec4(paletteLevel(int(c.x) & 1023), 0.0);
}
