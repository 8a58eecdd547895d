#include "ridge/lod/resident_cover.h"

#include "ridge/core/error.h"

#include <unordered_map>

namespace ridge::lod {

ResidentCover residentCover(const Selection& selection, const PyramidGeometry& geometry,
                            const std::function<bool(PatchId)>& resident)
{
    ResidentCover out;
    std::unordered_map<int64_t, SelectedPatch> chosen;
    for (const SelectedPatch& s : selection.patches) {
        PatchId a = s.id;
        while (!resident(a)) {
            if (a.level == 0)
                throw Error("resident cover: the root patch is not resident");
            a = a.parent();
        }
        if (!(a == s.id))
            ++out.missing;
        SelectedPatch drawn = s;
        drawn.id = a;
        chosen.emplace(geometry.patchIndex(a), drawn);
    }
    // Keep only patches without a chosen ancestor: an ancestor covers them.
    for (const auto& [key, s] : chosen) {
        bool covered = false;
        for (PatchId a = s.id; a.level > 0 && !covered;) {
            a = a.parent();
            covered = chosen.count(geometry.patchIndex(a)) > 0;
        }
        if (!covered)
            out.patches.push_back(s);
    }
    return out;
}

} // namespace ridge::lod
