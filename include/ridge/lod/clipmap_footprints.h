#pragma once
// The footprints of geometry clipmaps (the thesis §3.3, after Asirvatham & Hoppe, Figure 2.9):
// a few constant grids, built once and reused for every level, each placed by an offset in
// its level's cells. A level's ring is 12 m × m blocks, 4 fix-ups (m × 3) between them, the
// L-shaped interior trim ((2m + 1) × 2 and 2m × 2) on the side of the hole the finer level
// leaves, and degenerate triangles on the outer perimeter; the finest drawn level fills its
// hole as well (4 more blocks, 4 more fix-ups and the 3 × 3 centre). m = (n + 1)/4, so a ring
// row is 4(m − 1) + 2 = n − 1 cells. Indices are 16 bits (a block of m ≤ 256 has at most
// 65 536 vertices).
//
// The perimeter's triangles join each two outer cells' three vertices (v_2i, v_2i+1, v_2i+2).
// In the level's own grid they are flat, but v_2i+1 sits on the coarser level's edge
// v_2i–v_2i+2 (the transition region takes it to the coarser surface there), so they close the
// T-junctions — and on a curved basis, where the coarser edge is a chord, the sliver between
// chord and surface — with every edge of the two levels shared by exactly two triangles.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace ridge::lod {

enum class FootprintKind : uint8_t {
    Block,     // m × m vertices
    FixUpV,    // 3 wide, m tall: between the blocks of a ring's top and bottom rows
    FixUpH,    // m wide, 3 tall: between the blocks of its left and right columns
    TrimV,     // 2 wide, 2m + 1 tall: the interior trim's column
    TrimH,     // 2m wide, 2 tall: the interior trim's row
    Centre,    // 3 × 3: the middle of the finest drawn level
    Perimeter, // the window's outer perimeter: degenerate triangles
};
constexpr int kFootprintKinds = 7;

struct Footprint {
    FootprintKind kind = FootprintKind::Block;
    int width = 0, height = 0;      // vertices a side (Perimeter: the window's n × n)
    std::vector<uint16_t> vertices; // (x, y) pairs, in cells from the piece's corner
    std::vector<uint16_t> indices;  // triangles
    size_t triangles() const { return indices.size() / 3; }
};

// The footprint of `kind` for windows of n = 4m − 1.
Footprint makeFootprint(FootprintKind kind, int m);

// One footprint placed in a level's window, at cells (x, y) from the window's sample (0, 0).
struct FootprintPiece {
    FootprintKind kind;
    int x, y;
    int width, height; // vertices a side (with makeFootprint's sizes)
};

// The pieces of one level: its ring, with the interior trim on the side the finer level
// leaves (finer_x, finer_y: ClipmapLevel) or, for the finest drawn level (`filled`), the
// whole square; the perimeter when a coarser level is drawn outside it (`perimeter`).
// Larger pieces first (drawn first, so the depth test rejects more of what follows: §3.5.4).
std::vector<FootprintPiece> levelPieces(int m, bool filled, int finer_x, int finer_y,
                                        bool perimeter);

} // namespace ridge::lod
