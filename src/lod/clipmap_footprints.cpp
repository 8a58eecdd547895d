#include "ridge/lod/clipmap_footprints.h"

#include "ridge/core/error.h"

#include <string>

namespace ridge::lod {
namespace {

// A grid of w × h vertices, two triangles a cell (a b c, b d c: the diagonal from the cell's
// north-east to its south-west corner, as every other grid of ridge's). Adjacent footprints
// share only their outer, axis-aligned edges, so any diagonal keeps them watertight; this
// one makes the coarser surface at a finer level's cell centre the mean of b and c, which is
// what the transition region blends towards (clipmaps.vert), as geomorph's morph target.
Footprint grid(FootprintKind kind, int w, int h)
{
    Footprint f;
    f.kind = kind;
    f.width = w;
    f.height = h;
    f.vertices.reserve(size_t(w) * h * 2);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            f.vertices.insert(f.vertices.end(), {uint16_t(x), uint16_t(y)});
    f.indices.reserve(size_t(w - 1) * (h - 1) * 6);
    for (int y = 0; y + 1 < h; ++y)
        for (int x = 0; x + 1 < w; ++x) {
            const uint32_t a = uint32_t(y * w + x), b = a + 1, c = a + uint32_t(w), d = c + 1;
            f.indices.insert(f.indices.end(), {uint16_t(a), uint16_t(b), uint16_t(c), uint16_t(b),
                                               uint16_t(d), uint16_t(c)});
        }
    return f;
}

// The 4(n − 1) vertices of an n × n window's perimeter, clockwise from (0, 0) in the grid
// (x east, y south), and one triangle per two perimeter cells.
Footprint perimeter(int n)
{
    Footprint f;
    f.kind = FootprintKind::Perimeter;
    f.width = f.height = n;
    const int side = n - 1;
    auto add = [&](int x, int y) {
        f.vertices.insert(f.vertices.end(), {uint16_t(x), uint16_t(y)});
    };
    for (int i = 0; i < side; ++i)
        add(i, 0);
    for (int i = 0; i < side; ++i)
        add(side, i);
    for (int i = 0; i < side; ++i)
        add(side - i, side);
    for (int i = 0; i < side; ++i)
        add(0, side - i);
    const int count = 4 * side; // side is even: every corner is an even vertex
    for (int i = 0; i < count; i += 2)
        f.indices.insert(f.indices.end(),
                         {uint16_t(i), uint16_t(i + 1), uint16_t((i + 2) % count)});
    return f;
}

} // namespace

Footprint makeFootprint(FootprintKind kind, int m)
{
    if (m < 4 || m > 256)
        throw Error("clipmap footprints: m " + std::to_string(m) + " outside 4..256");
    switch (kind) {
    case FootprintKind::Block:
        return grid(kind, m, m);
    case FootprintKind::FixUpV:
        return grid(kind, 3, m);
    case FootprintKind::FixUpH:
        return grid(kind, m, 3);
    case FootprintKind::TrimV:
        return grid(kind, 2, 2 * m + 1);
    case FootprintKind::TrimH:
        return grid(kind, 2 * m, 2);
    case FootprintKind::Centre:
        return grid(kind, 3, 3);
    case FootprintKind::Perimeter:
        return perimeter(4 * m - 1);
    }
    throw Error("clipmap footprints: unknown kind");
}

std::vector<FootprintPiece> levelPieces(int m, bool filled, int finer_x, int finer_y,
                                        bool perimeter)
{
    using K = FootprintKind;
    std::vector<FootprintPiece> out;
    // Block corners along an axis: 0, m − 1, (the 2-cell fix-up gap at 2m − 2), 2m, 3m − 1.
    const int at[4] = {0, m - 1, 2 * m, 3 * m - 1};
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) {
            const bool inner = (i == 1 || i == 2) && (j == 1 || j == 2);
            if (!inner || filled)
                out.push_back({K::Block, at[i], at[j], m, m});
        }
    const int gap = 2 * m - 2;
    // The ring's fix-ups: top, bottom (3 wide), left, right (3 tall).
    out.push_back({K::FixUpV, gap, 0, 3, m});
    out.push_back({K::FixUpV, gap, 3 * m - 1, 3, m});
    out.push_back({K::FixUpH, 0, gap, m, 3});
    out.push_back({K::FixUpH, 3 * m - 1, gap, m, 3});
    if (filled) {
        out.push_back({K::FixUpV, gap, m - 1, 3, m});
        out.push_back({K::FixUpV, gap, 2 * m, 3, m});
        out.push_back({K::FixUpH, m - 1, gap, m, 3});
        out.push_back({K::FixUpH, 2 * m, gap, m, 3});
        out.push_back({K::Centre, gap, gap, 3, 3});
    } else {
        // The hole is cells [m − 1, 3m − 1) a side; the finer level fills 2m − 1 of them from
        // m − 1 + finer, the trim the one left: a column the hole's height, then a row across
        // the rest.
        const int trim_x = finer_x == 0 ? 3 * m - 2 : m - 1;
        const int trim_y = finer_y == 0 ? 3 * m - 2 : m - 1;
        out.push_back({K::TrimV, trim_x, m - 1, 2, 2 * m + 1});
        out.push_back({K::TrimH, finer_x == 0 ? m - 1 : m, trim_y, 2 * m, 2});
    }
    if (perimeter)
        out.push_back({K::Perimeter, 0, 0, 4 * m - 1, 4 * m - 1});
    return out;
}

} // namespace ridge::lod
