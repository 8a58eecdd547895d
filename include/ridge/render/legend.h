#pragma once
// Colour keys of the debug colour modes (`render --mode lod|tess`, the viewer's F2/F3): which
// colour is which quadtree level or tessellation factor, from the palette the shader is given
// (ridge/core/terrain_palette.h). GL-free: the headless PNG gets it drawn into its pixels
// (drawLegend), the viewer shows the same entries in its overlay.
#include "ridge/core/terrain_palette.h"
#include "ridge/render/terrain_renderer.h"

#include <cstdint>
#include <string>
#include <vector>

namespace ridge::render {

struct LegendEntry {
    std::string label; // digits only (the PNG's font has nothing else)
    palette::Rgb colour;
};

// The entries of `mode`: levels 0 .. finest_level (LodLevels), factors 1, 2, 4 .. block_cells
// (TessellationFactors; the tessellator's factors are b / 2^d); nothing for Shaded.
std::vector<LegendEntry> legendEntries(DebugMode mode, int finest_level, int block_cells);

// Draws `entries` into the bottom-left corner of an image of `width` × `height` pixels,
// `channels` (3 or 4) bytes each, rows top first: a dark panel with one swatch and label per
// entry, in as many columns as fit. An image too small for one entry is left as it is.
// Labels use a 3×5 bitmap digit font drawn at 2× (hand-written: ten glyphs of 15 bits are
// smaller than any font dependency, and the output must not depend on installed fonts).
void drawLegend(uint8_t* pixels, int width, int height, int channels,
                const std::vector<LegendEntry>& entries);

} // namespace ridge::render
