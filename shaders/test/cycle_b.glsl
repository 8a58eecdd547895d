// See test/cycle_a.glsl.
#include "test/cycle_a.glsl"
