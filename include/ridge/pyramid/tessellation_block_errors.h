#pragma once
// Tessellation block errors λ(d) ("Tessellation Blocks", Yusov & Shevtsov 2011, §5).
//
// A patch of C cells per side is split into (C/b)^2 tessellation blocks of b cells
// (b + 1 samples, default 8 cells = 9x9 samples). The GPU may draw a block with its
// triangulation simplified by 2^d; λ(d) is the largest vertical distance from a patch
// sample of the block that the simplified triangulation skips to that triangulation:
//
//   λ_{r,s}^(d) = max_{v ∉ T_{r,s}^(d)} ρ(v, T_{r,s}^(d)),   d = 1 .. D,  D = min(4, log2 b)
//
// As for Err_Int we take, per simplified cell, the worst of its bilinear interpolant and of
// both diagonal triangulations, so λ does not depend on the diagonal the tessellator picks
// (the bilinear value lies between the two triangulations, so the triangulations decide).
// The renderer adds Err(P): Λ^(d) = λ^(d) + Err(P).
#include <cstdint>

namespace ridge {

struct TessellationBlockLayout {
    int patch_size = 129; // samples per patch side, 2^n + 1
    int block_cells = 8;  // cells per block side, 2^k, 2 <= b <= patch cells

    int blocksPerSide() const { return (patch_size - 1) / block_cells; }
    // D: the number of simplification levels stored (d = 1..D).
    int levels() const;
    int valuesPerPatch() const { return blocksPerSide() * blocksPerSide() * levels(); }
    bool valid() const;
};

// λ for every block of one patch, in code units:
// out[((r * blocksPerSide()) + s) * levels() + (d - 1)], r = block row, s = block column.
// `patch` holds patch_size^2 codes, row-major.
void computeTessellationBlockErrors(const uint16_t* patch, const TessellationBlockLayout& layout,
                                    float* out);

} // namespace ridge
