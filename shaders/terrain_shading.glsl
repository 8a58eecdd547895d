// The terrain's colour at a fragment, shared by the schemes' fragment stages (terrain.frag,
// clipmaps.frag): sun light, the hypsometric palette of ridge/core/terrain_palette.h
// (palette.glsl, shared with `ridge hillshade`), slope shading, distance fog (exponential
// height fog on the globe); debug modes for LOD levels and tessellation factors. Each stage
// finds the surface's normal, height and water at the fragment its own way; this is the rest.
// Needs terrain_common.glsl (localBasis, u_exaggeration) and palette.glsl included first.
uniform int u_mode;             // 0 shaded, 1 LOD level colours, 2 tessellation-factor heat map, 3 flat colour
uniform vec3 u_flat_colour;     // mode 3 (wireframe overlay)
uniform vec3 u_sun_direction;   // unit, towards the sun, terrain frame (ECEF on the globe)
uniform vec2 u_height_range;    // camera-relative z of the terrain's min and max
uniform float u_sea_level;      // camera-relative z of 0 m
uniform vec3 u_fog_colour;
uniform float u_fog_density;    // per metre (at sea level on the globe); 0 disables fog
// Globe: the air's scale height (metres; 0 on the plane, whose fog is uniform). The fog then
// follows the air the ray crosses, thinning with altitude (exponential height fog).
uniform float u_fog_scale_height;
uniform int u_block_cells_f;    // b, for the heat map

// The colour at camera-relative `position` of a surface with local (east, north, up) normal
// `n` (ignored on a wall: a flat vertical face, lit by its own normal), true height `metres`
// and `water`; `level` and `factor` for the debug modes 1 and 2.
vec4 shadeTerrain(vec3 position, vec3 n, float metres, bool water, int level, float factor,
                  bool wall) {
    // Normals are local (east, north, up); on the globe the frame turns with the fragment.
    mat3 basis = localBasis(position);
    if (wall) {
        n = normalize(cross(dFdx(position), dFdy(position)));
        if (dot(n, position) > 0.0)
            n = -n; // towards the viewer
        n = transpose(basis) * n;
    }
    float slope = 1.0 - n.z; // 0 flat .. 1 vertical
    vec3 albedo;
    if (u_mode == 1)
        albedo = paletteLevel(level);
    else if (u_mode == 2)
        albedo = paletteHeat(log2(max(factor, 1.0)) / max(log2(float(u_block_cells_f)), 1.0));
    else {
        float min_m = (u_height_range.x - u_sea_level) / u_exaggeration;
        float max_m = (u_height_range.y - u_sea_level) / u_exaggeration;
        albedo = paletteTerrain(metres, water, min_m, max_m);
        if (!water) {
            float low = max(min_m, 0.0);
            float t = (metres - low) / max(max_m - low, 1e-3);
            if (wall)
                albedo = mix(albedo, vec3(0.36, 0.29, 0.22), 0.6); // walls: earth
            // Steep rock shows through below the snow line.
            albedo = mix(albedo, vec3(0.42, 0.39, 0.36), smoothstep(0.25, 0.55, slope) * (1.0 - step(0.9, t)));
        }
    }
    float sun = max(dot(n, transpose(basis) * u_sun_direction), 0.0);
    float sky = 0.5 + 0.5 * n.z;
    vec3 colour = albedo * (0.78 * sun + 0.30 * sky);
    if (u_fog_density > 0.0) {
        float distance = length(position);
        float depth = u_fog_density * distance; // optical depth, uniform air
        if (u_fog_scale_height > 0.0) {
            // Density ∝ exp(−h / H) along the straight ray from the camera (altitude −u_sea_level
            // in drawn metres) to the fragment: τ = β0 L H (e^(−hc/H) − e^(−hf/H)) / (hf − hc),
            // and β0 L e^(−hc/H) for a level ray.
            float H = u_fog_scale_height;
            float hc = -u_sea_level;           // the camera's, drawn metres
            float hf = metres * u_exaggeration; // the fragment's
            float dh = hf - hc;
            float ec = exp(-hc / H), ef = exp(-hf / H);
            depth = abs(dh) > 1.0 ? u_fog_density * distance * H * (ec - ef) / dh
                                  : u_fog_density * distance * ec;
        }
        colour = mix(colour, u_fog_colour, 1.0 - exp(-depth));
    }
    return vec4(pow(colour, vec3(1.0 / 1.1)), 1.0);
}
