#version 450 core
// Scheme clipmaps: writes a rectangle of one level's window into its texture from one
// resident patch (lod::ClipmapWrite), addressed toroidally: the level's sample (i, j) lives at
// texel (i mod N, j mod N), N = n + 1, so a level shift writes only its new L-shaped strip and
// nothing already there moves (the thesis §3.5.2, Figure 3.8). Per texel: the sample's code,
// and flags — bit 0: the cell south-east of it may be drawn (kept nodata), bit 1: the sample
// is water. Samples beyond the terrain take the patch's edge samples (the clip stage cuts the
// surface on the border; they only shape the cut). A level coarser than the archive's level 0
// reads every 2^d-th sample of the root. On a globe whose columns go round the Earth the
// windows' columns run on across the antimeridian: a write reads them a whole number of turns
// back.
layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = 0) uniform usampler2DArray u_heights;    // codes, one layer per slot
layout(binding = 4) uniform usampler2DArray u_cell_masks; // 1 = drawable, per cell
layout(binding = 5) uniform usampler1D u_mask_flags;      // per slot: 1 mask, 2 water map, 4 all water
layout(binding = 6) uniform usampler2DArray u_water_maps; // bit 0: water, per sample
layout(rg16ui, binding = 0) uniform writeonly uimage2DArray u_level;

uniform ivec4 u_rect;          // the level's samples [x0, x1) × [y0, y1)
uniform int u_layer;           // the level
uniform int u_texture_size;    // N, a power of two
uniform int u_slot;            // the patch's slot
uniform ivec2 u_patch_origin;  // the patch's sample (0, 0) in its archive level's samples
uniform int u_wrap_shift;      // level samples: sample i is read as i − shift (whole turns)
uniform int u_decimation;      // archive-level samples per level sample (1, or 2^d for the root)
uniform ivec2 u_level_last;    // the archive level's last samples (levelWidth − 1, levelHeight − 1)
uniform int u_patch_cells;     // C

void main() {
    ivec2 g = u_rect.xy + ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(g, u_rect.zw)))
        return;
    ivec2 s = clamp((g - ivec2(u_wrap_shift, 0)) * u_decimation, ivec2(0), u_level_last) - u_patch_origin;
    s = clamp(s, ivec2(0), ivec2(u_patch_cells));
    uint code = texelFetch(u_heights, ivec3(s, u_slot), 0).r;
    uint mask_flags = texelFetch(u_mask_flags, u_slot, 0).r;
    uint flags = 1u;
    if ((mask_flags & 1u) != 0u) {
        ivec2 cell = min(s, ivec2(u_patch_cells - 1));
        flags = texelFetch(u_cell_masks, ivec3(cell, u_slot), 0).r != 0u ? 1u : 0u;
    }
    if ((mask_flags & 4u) != 0u)
        flags |= 2u;
    else if ((mask_flags & 2u) != 0u)
        flags |= (texelFetch(u_water_maps, ivec3(s, u_slot), 0).r & 1u) << 1;
    ivec2 texel = g & ivec2(u_texture_size - 1); // two's complement: the positive remainder
    imageStore(u_level, ivec3(texel, u_layer), uvec4(code, flags, 0u, 0u));
}
