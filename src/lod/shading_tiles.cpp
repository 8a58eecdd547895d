#include "ridge/lod/shading_tiles.h"

#include "ridge/core/error.h"

namespace ridge::lod {
namespace {

// Writes `word` over the tiles `p` covers (`below` levels under `drawn`), then lets each
// resident child (or its resident descendants) overwrite its quarter: finest wins.
void fill(PatchId drawn, PatchId p, int below, uint32_t word, const PyramidGeometry& geometry,
          const std::function<int(PatchId)>& slot_of, ShadingTiles& out)
{
    const int side = kShadingTiles >> below; // tiles a side of p
    const int x0 = (p.x - (drawn.x << below)) * side;
    const int y0 = (p.y - (drawn.y << below)) * side;
    for (int y = y0; y < y0 + side; ++y)
        for (int x = x0; x < x0 + side; ++x)
            out[size_t(y) * kShadingTiles + size_t(x)] = word;
    if (below == kShadingDepth)
        return;
    for (int k = 0; k < 4; ++k) {
        const PatchId child{p.level + 1, 2 * p.x + (k & 1), 2 * p.y + (k >> 1)};
        if (!geometry.exists(child))
            continue; // beyond the extent: nothing is drawn there
        const int slot = slot_of(child);
        // A missing child keeps its parent's word, but its own children may be resident
        // (decoded on the CPU, a patch needs no resident parent).
        fill(drawn, child, below + 1, slot >= 0 ? shadingTile(slot, below + 1) : word, geometry,
             slot_of, out);
    }
}

} // namespace

uint32_t shadingTile(int slot, int levels_below)
{
    if (slot < 0 || slot >= (1 << 24) - 1 || levels_below < 1 || levels_below > kShadingDepth)
        throw Error("shading tile: slot " + std::to_string(slot) + " " +
                    std::to_string(levels_below) + " levels below is out of range");
    return uint32_t(slot + 1) | (uint32_t(levels_below) << 24);
}

void shadingTiles(PatchId drawn, const PyramidGeometry& geometry,
                  const std::function<int(PatchId)>& slot_of, ShadingTiles& out)
{
    if (drawn.level >= geometry.finestLevel()) {
        out.fill(0u);
        return;
    }
    fill(drawn, drawn, 0, 0u, geometry, slot_of, out);
}

} // namespace ridge::lod
