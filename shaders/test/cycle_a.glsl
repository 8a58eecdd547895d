// Includes test/cycle_b.glsl, which includes this file again: shaderSource must reject it.
#include "test/cycle_b.glsl"
