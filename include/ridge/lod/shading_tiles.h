#pragma once
// Texture detail decoupled from geometry (issue 28): where a drawn patch's fragments shade
// from. A drawn patch is split into kShadingTiles × kShadingTiles tiles (2^kShadingDepth a
// side); each tile names the finest resident patch covering it among the drawn patch's
// descendants down to kShadingDepth levels below (lod::Selection::detail is what the streaming
// planner fetches for them), or the drawn patch itself. The fragment stage then reads heights,
// normals and water of that patch's level while the triangles stay the drawn patch's: a
// coarse mesh shows the texels of whatever finer data is resident under it.
//
// One tile is a uint32: 0 for the drawn patch itself, otherwise (slot + 1) | (k << 24) with k
// in 1..kShadingDepth the levels below it (shaders/terrain.frag decodes it). Plain C++: the
// renderer's ShadingMap uploads what this computes.
#include "ridge/lod/patch_quadtree.h"

#include <array>
#include <cstdint>
#include <functional>

namespace ridge::lod {

inline constexpr int kShadingTiles = 1 << kShadingDepth;
using ShadingTiles = std::array<uint32_t, size_t(kShadingTiles) * kShadingTiles>; // row-major

// The tile word for the patch in `slot`, `levels_below` the drawn patch (1..kShadingDepth).
uint32_t shadingTile(int slot, int levels_below);

// The tiles of `drawn` (a patch of `geometry`): the finest patch with slot_of(p) >= 0 over
// each tile. slot_of is asked about descendants only; slots must be below 2^24.
void shadingTiles(PatchId drawn, const PyramidGeometry& geometry,
                  const std::function<int(PatchId)>& slot_of, ShadingTiles& out);

} // namespace ridge::lod
