#include "ridge/lod/skirt_depth.h"

#include <algorithm>
#include <unordered_map>

namespace ridge::lod {
namespace {

using SelectedIndex = std::unordered_map<int64_t, size_t>; // patch index -> position

// Selected patches covering the part of same-level patch `q` that touches side `side` of its
// neighbour (0: q is west of it, so q's east side; 1: east/west side; 2: north; 3: south).
void collectTowards(const PyramidGeometry& g, const SelectedIndex& index, PatchId q, int side,
                    std::vector<size_t>& out)
{
    if (!g.exists(q))
        return;
    // An ancestor (or q itself) selected: it alone covers the seam.
    for (PatchId a = q;; a = PatchId{a.level - 1, a.x / 2, a.y / 2}) {
        if (auto it = index.find(g.patchIndex(a)); it != index.end()) {
            out.push_back(it->second);
            return;
        }
        if (a.level == 0)
            break;
    }
    // Otherwise finer patches are selected: descend along the facing side.
    std::vector<PatchId> stack{q};
    while (!stack.empty()) {
        const PatchId p = stack.back();
        stack.pop_back();
        if (p.level == g.finestLevel())
            continue;
        for (int k = 0; k < 4; ++k) {
            const int cx = k & 1, cy = k >> 1;
            // Keep only children on the side facing the neighbour.
            if ((side == 0 && cx != 1) || (side == 1 && cx != 0) || (side == 2 && cy != 1) ||
                (side == 3 && cy != 0))
                continue;
            const PatchId c{p.level + 1, 2 * p.x + cx, 2 * p.y + cy};
            if (!g.exists(c))
                continue;
            if (auto it = index.find(g.patchIndex(c)); it != index.end())
                out.push_back(it->second);
            else
                stack.push_back(c);
        }
    }
}

std::vector<size_t> neighboursOf(const PyramidGeometry& g, const SelectedIndex& index, PatchId p)
{
    std::vector<size_t> out;
    collectTowards(g, index, {p.level, p.x - 1, p.y}, 0, out); // west neighbour's east side
    collectTowards(g, index, {p.level, p.x + 1, p.y}, 1, out);
    collectTowards(g, index, {p.level, p.x, p.y - 1}, 2, out); // north neighbour's south side
    collectTowards(g, index, {p.level, p.x, p.y + 1}, 3, out);
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

SelectedIndex indexOf(const PyramidGeometry& g, const std::vector<PatchId>& selected)
{
    SelectedIndex index;
    for (size_t i = 0; i < selected.size(); ++i)
        index[g.patchIndex(selected[i])] = i;
    return index;
}

} // namespace

std::vector<size_t> seamNeighbours(const PatchQuadtree& tree, const std::vector<PatchId>& selected,
                                   size_t i)
{
    return neighboursOf(tree.geometry(), indexOf(tree.geometry(), selected), selected[i]);
}

std::vector<double> skirtDepths(const PatchQuadtree& tree, const std::vector<PatchId>& selected,
                                const std::function<double(PatchId)>& max_deviation, double margin)
{
    const PyramidGeometry& g = tree.geometry();
    const SelectedIndex index = indexOf(g, selected);
    std::vector<double> deviation(selected.size());
    for (size_t i = 0; i < selected.size(); ++i)
        deviation[i] = max_deviation(selected[i]);
    std::vector<double> depths(selected.size());
    for (size_t i = 0; i < selected.size(); ++i) {
        double worst_neighbour = 0.0;
        for (size_t j : neighboursOf(g, index, selected[i]))
            worst_neighbour = std::max(worst_neighbour, deviation[j]);
        depths[i] = deviation[i] + worst_neighbour + margin;
    }
    return depths;
}

} // namespace ridge::lod
