#pragma once
// A patch's heights with a one-sample ring taken from its same-level neighbours, so that
// central differences (normal maps) at the patch border see the same samples as the
// neighbour does at its border: shading is continuous across seams between patches of one
// level. The paper compresses (2^n+3)^2 patches for this; ridge archives store (2^n+1)^2 and
// borrow the ring from the neighbours instead.
#include <cstdint>
#include <vector>

namespace ridge::stream {

// West, east, north, south neighbours' codes (patch_size^2 each, row-major), null where there
// is none (terrain border). Returns (n+2)^2 values in code units, row-major, with sample
// (i, j) of the patch at (i+1, j+1). Where a neighbour is missing the ring is linearly
// extrapolated (2·h0 − h1), so a central difference there equals the one-sided one; corners
// are never read by central differences and hold the nearest ring value.
std::vector<float> borderedPatch(const uint16_t* codes, int n, const uint16_t* west,
                                 const uint16_t* east, const uint16_t* north,
                                 const uint16_t* south);

} // namespace ridge::stream
