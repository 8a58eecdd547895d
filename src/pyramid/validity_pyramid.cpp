// The validity pyramid: sample validity level by level from the finest (decimation: the
// sample at the same position; Neville-4: every sample of the filter's support), and cell
// drawability as the AND of the four child cells, from the finest cells (AND of their four
// corners) up: a level-l cell's footprint is the union of its children's.
#include "ridge/pyramid/validity_pyramid.h"

#include "ridge/core/error.h"

#include <algorithm>

namespace ridge {

void PatchValidity::canonicalize()
{
    if (kind != Kind::Mixed)
        return;
    const auto all = [](const std::vector<uint8_t>& v, uint8_t value) {
        return std::all_of(v.begin(), v.end(), [&](uint8_t b) { return (b != 0) == (value != 0); });
    };
    if (all(samples, 1) && all(cells, 1))
        kind = Kind::AllValid;
    else if (all(samples, 0) && all(cells, 0))
        kind = Kind::NoneValid;
    if (kind != Kind::Mixed) {
        samples.clear();
        cells.clear();
    }
}

ValidityPyramid::ValidityPyramid(const std::vector<uint8_t>& nodata,
                                 const PyramidGeometry& geometry, PyramidFilter filter)
    : geometry_(geometry)
{
    const int W = geometry.width(), H = geometry.height(), L = geometry.finestLevel();
    if (nodata.size() != static_cast<size_t>(W) * H)
        throw Error("internal error: nodata mask of " + std::to_string(nodata.size()) +
                    " samples for a " + std::to_string(W) + " x " + std::to_string(H) + " grid");
    samples_.resize(L + 1);
    cells_.resize(L + 1);
    Grid& finest = samples_[L];
    finest.width = W;
    finest.height = H;
    finest.bits.resize(nodata.size());
    for (size_t i = 0; i < nodata.size(); ++i)
        finest.bits[i] = nodata[i] == 0;

    for (int l = L - 1; l >= 0; --l) {
        const Grid& fine = samples_[l + 1];
        Grid& g = samples_[l];
        g.width = geometry.levelWidth(l);
        g.height = geometry.levelHeight(l);
        g.bits.assign(static_cast<size_t>(g.width) * g.height, false);
        const int reach = filter == PyramidFilter::Neville4 ? 4 : 0;
        for (int j = 0; j < g.height; ++j)
            for (int i = 0; i < g.width; ++i) {
                uint8_t v = 1;
                for (int b = -reach; b <= reach && v; ++b)
                    for (int a = -reach; a <= reach && v; ++a)
                        v = fine.at(2 * int64_t{i} + a, 2 * int64_t{j} + b);
                g.bits[static_cast<size_t>(j) * g.width + i] = v != 0;
            }
    }

    Grid& finest_cells = cells_[L];
    finest_cells.width = W - 1;
    finest_cells.height = H - 1;
    finest_cells.bits.resize(static_cast<size_t>(W - 1) * (H - 1));
    for (int j = 0; j < H - 1; ++j)
        for (int i = 0; i < W - 1; ++i)
            finest_cells.bits[static_cast<size_t>(j) * (W - 1) + i] =
                (finest.at(i, j) & finest.at(i + 1, j) & finest.at(i, j + 1) &
                 finest.at(i + 1, j + 1)) != 0;
    for (int l = L - 1; l >= 0; --l) {
        const Grid& fine = cells_[l + 1];
        Grid& g = cells_[l];
        g.width = geometry.levelWidth(l) - 1;
        g.height = geometry.levelHeight(l) - 1;
        g.bits.resize(static_cast<size_t>(g.width) * g.height);
        for (int j = 0; j < g.height; ++j)
            for (int i = 0; i < g.width; ++i)
                g.bits[static_cast<size_t>(j) * g.width + i] =
                    (fine.at(2 * int64_t{i}, 2 * int64_t{j}) &
                     fine.at(2 * int64_t{i} + 1, 2 * int64_t{j}) &
                     fine.at(2 * int64_t{i}, 2 * int64_t{j} + 1) &
                     fine.at(2 * int64_t{i} + 1, 2 * int64_t{j} + 1)) != 0;
    }
}

bool ValidityPyramid::sampleValid(int level, int64_t i, int64_t j) const
{
    return samples_[level].at(i, j) != 0;
}

bool ValidityPyramid::cellDrawable(int level, int64_t i, int64_t j) const
{
    return cells_[level].at(i, j) != 0;
}

PatchValidity ValidityPyramid::patch(PatchId p) const
{
    const int n = geometry_.patchSize(), c = n - 1;
    PatchValidity v;
    v.kind = PatchValidity::Kind::Mixed;
    v.patch_size = n;
    v.samples.resize(static_cast<size_t>(n) * n);
    v.cells.resize(static_cast<size_t>(c) * c);
    const int64_t x0 = int64_t{p.x} * c, y0 = int64_t{p.y} * c;
    const Grid& s = samples_[p.level];
    const Grid& d = cells_[p.level];
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i)
            v.samples[static_cast<size_t>(j) * n + i] = s.at(x0 + i, y0 + j);
    for (int j = 0; j < c; ++j)
        for (int i = 0; i < c; ++i)
            v.cells[static_cast<size_t>(j) * c + i] = d.at(x0 + i, y0 + j);
    v.canonicalize();
    return v;
}

} // namespace ridge
