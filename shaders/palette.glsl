// The GLSL half of ridge/core/terrain_palette.h: the same piecewise-linear lookups over the
// C++ tables, which the renderer sends as these uniforms (render::setPaletteUniforms). No
// colour is written here; tests/render/palette_twin_test.cpp checks both halves agree.
uniform vec4 u_land_stops[6];  // (t, r, g, b), t increasing
uniform vec4 u_water_stops[2];
uniform vec3 u_level_colours[8];

vec3 paletteRamp6(float t) {
    t = t >= 0.0 ? min(t, 1.0) : 0.0;
    for (int k = 1; k < 6; ++k)
        if (t <= u_land_stops[k].x)
            return mix(u_land_stops[k - 1].yzw, u_land_stops[k].yzw,
                       (t - u_land_stops[k - 1].x) / (u_land_stops[k].x - u_land_stops[k - 1].x));
    return u_land_stops[5].yzw;
}

vec3 paletteWater(float t) {
    t = t >= 0.0 ? min(t, 1.0) : 0.0;
    return mix(u_water_stops[0].yzw, u_water_stops[1].yzw,
               (t - u_water_stops[0].x) / (u_water_stops[1].x - u_water_stops[0].x));
}

// The water rule of archives without sample flags (palette::isWater).
bool paletteIsWater(float metres) { return metres <= 0.0; }

// Albedo at `metres` on a terrain spanning [min_metres, max_metres], water or land
// (palette::terrainColour).
vec3 paletteTerrain(float metres, bool water, float min_metres, float max_metres) {
    if (water)
        return paletteWater(min_metres < 0.0 ? metres / min_metres : 0.0);
    float low = max(min_metres, 0.0);
    return paletteRamp6((metres - low) / max(max_metres - low, 1e-3));
}

vec3 paletteHeat(float t) {
    return clamp(vec3(1.5 - abs(4.0 * t - 3.0), 1.5 - abs(4.0 * t - 2.0), 1.5 - abs(4.0 * t - 1.0)),
                 0.0, 1.0);
}

vec3 paletteLevel(int level) { return u_level_colours[abs(level) % 8]; }
