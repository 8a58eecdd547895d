#pragma once
// The colours ridge paints terrain with, in one place: the hypsometric tint and water of
// `ridge hillshade` and of the renderers' shaded mode, the LOD level colours and the
// tessellation-factor heat map of the debug modes (and their legends). Plain C++: the
// renderer sends these tables to shaders/palette.glsl as uniforms, so the GLSL holds no
// colour of its own, only the same piecewise-linear lookup (checked against this one at many
// heights by tests/render/palette_twin_test.cpp).
//
// Water is not a height: archives of format 4 flag it per sample (pyramid/sample_flags.h,
// decided at build from the source's exact heights and any water layer), and the palette
// takes the flag. Archives before format 4 have no flags: isWater (a height <= 0 m is sea)
// is the rule they are painted by, which a lossy height (a 0 m sea decoded as +1 m) and any
// lake or land below sea level break.
#include <array>
#include <cstddef>

namespace ridge::palette {

struct Rgb {
    float r = 0.f, g = 0.f, b = 0.f;
};

struct Stop {
    float t = 0.f; // position along the ramp, [0, 1], increasing
    Rgb colour;
};

// Land: lowland green, upland ochre, brown, grey rock, snow over t = (h − land_low) /
// (land_high − land_low), land_low = max(min height, 0) and land_high the terrain's maximum.
inline constexpr std::array<Stop, 6> kLandStops = {{
    {0.00f, {0.27f, 0.47f, 0.29f}},
    {0.25f, {0.55f, 0.65f, 0.38f}},
    {0.50f, {0.82f, 0.76f, 0.55f}},
    {0.70f, {0.66f, 0.52f, 0.40f}},
    {0.85f, {0.60f, 0.58f, 0.56f}},
    {1.00f, {0.97f, 0.97f, 0.98f}},
}};
// Water: shallow (0 m) to deep (the terrain's minimum) over t = h / min height.
inline constexpr std::array<Stop, 2> kWaterStops = {{
    {0.00f, {0.24f, 0.42f, 0.62f}},
    {1.00f, {0.08f, 0.16f, 0.34f}},
}};
// Debug mode "lod": level l is kLevelColours[l % 8].
inline constexpr std::array<Rgb, 8> kLevelColours = {{
    {0.90f, 0.10f, 0.10f},
    {0.95f, 0.55f, 0.10f},
    {0.95f, 0.90f, 0.15f},
    {0.30f, 0.80f, 0.20f},
    {0.10f, 0.70f, 0.80f},
    {0.20f, 0.35f, 0.90f},
    {0.60f, 0.25f, 0.85f},
    {0.85f, 0.85f, 0.85f},
}};

// Piecewise-linear colour of `stops` at t (clamped to [0, 1]).
template <std::size_t N> Rgb ramp(const std::array<Stop, N>& stops, float t);

// The shaded mode's albedo (before light) at `metres` on a terrain whose heights span
// [min_metres, max_metres]: the water ramp where `water` (deeper below 0 m towards the
// terrain's minimum; a lake above sea level is shallow), the land ramp elsewhere. Both ends
// finite.
Rgb terrainColour(float metres, bool water, float min_metres, float max_metres);
// The water rule of archives without sample flags (format < 4): at or below 0 m.
bool isWater(float metres);

// Debug mode "tess": the heat map of t = log2(factor) / log2(block cells), 0 blue (coarse)
// .. 1 red (full resolution).
Rgb heat(float t);
// Debug mode "lod": the colour of quadtree level `level`.
Rgb levelColour(int level);

} // namespace ridge::palette
