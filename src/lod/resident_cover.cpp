#include "ridge/lod/resident_cover.h"

#include "ridge/core/error.h"

#include <algorithm>
#include <cstddef>

namespace ridge::lod {

namespace {

PatchId finestResidentAncestor(PatchId p, const std::function<bool(PatchId)>& resident)
{
    while (!resident(p)) {
        if (p.level == 0)
            throw Error("resident cover: the root patch is not resident");
        p = p.parent();
    }
    return p;
}

// Merges entries with the same id (sorted next to each other) into the first: an ancestor
// drawn for several patches is as far off as the worst of them and only as surely inside
// the frustum as the least sure.
void mergeDuplicates(std::vector<SelectedPatch>& patches)
{
    size_t out = 0;
    for (size_t k = 0; k < patches.size(); ++k) {
        if (out > 0 && patches[out - 1].id == patches[k].id) {
            SelectedPatch& kept = patches[out - 1];
            kept.screen_error = std::max(kept.screen_error, patches[k].screen_error);
            kept.rank = std::max(kept.rank, patches[k].rank);
            kept.visibility = std::min(kept.visibility, patches[k].visibility);
        } else {
            patches[out++] = patches[k];
        }
    }
    patches.resize(out);
}

// Whether an ancestor of `p` is in [first, last), sorted by patch index.
bool hasAncestorIn(PatchId p, std::vector<SelectedPatch>::const_iterator first,
                   std::vector<SelectedPatch>::const_iterator last, const PyramidGeometry& geometry)
{
    auto before = [&](const SelectedPatch& s, int64_t key) {
        return geometry.patchIndex(s.id) < key;
    };
    while (p.level > 0) {
        p = p.parent();
        auto it = std::lower_bound(first, last, geometry.patchIndex(p), before);
        if (it != last && it->id == p)
            return true;
    }
    return false;
}

// Drops patches with an ancestor in the list: the ancestor covers them. Patch indices run
// coarse to fine, so an ancestor precedes its descendants and the kept prefix is the list to
// search (a dropped ancestor has a kept one of its own, which covers the descendant too).
void dropCovered(std::vector<SelectedPatch>& sorted, const PyramidGeometry& geometry)
{
    size_t out = 0;
    for (size_t k = 0; k < sorted.size(); ++k)
        if (!hasAncestorIn(sorted[k].id, sorted.begin(), sorted.begin() + std::ptrdiff_t(out),
                           geometry))
            sorted[out++] = sorted[k];
    sorted.resize(out);
}

} // namespace

void residentCover(const Selection& selection, const PyramidGeometry& geometry,
                   const std::function<bool(PatchId)>& resident, ResidentCover& out)
{
    out.patches.clear();
    out.missing = 0;
    for (const SelectedPatch& s : selection.patches) {
        SelectedPatch drawn = s;
        drawn.id = finestResidentAncestor(s.id, resident);
        out.missing += !(drawn.id == s.id);
        out.patches.push_back(drawn);
    }
    // Sorted by patch index, in place: no scratch set, and ancestors come before descendants.
    std::sort(out.patches.begin(), out.patches.end(),
              [&](const SelectedPatch& a, const SelectedPatch& b) {
                  return geometry.patchIndex(a.id) < geometry.patchIndex(b.id);
              });
    mergeDuplicates(out.patches);
    dropCovered(out.patches, geometry);
}

ResidentCover residentCover(const Selection& selection, const PyramidGeometry& geometry,
                            const std::function<bool(PatchId)>& resident)
{
    ResidentCover out;
    residentCover(selection, geometry, resident, out);
    return out;
}

} // namespace ridge::lod
