#pragma once
// What to draw while patches stream in: the selection with every patch that is not resident
// replaced by its finest resident ancestor (the paper's fallback: "until a patch arrives its
// finest resident ancestor is drawn"). An ancestor stands in for all of its area, so any
// selected patch under a drawn ancestor is dropped: the cover tiles exactly the area of the
// selection, with no hole and no overlap, as long as the root is resident.
#include "ridge/lod/patch_quadtree.h"

#include <functional>
#include <vector>

namespace ridge::lod {

struct ResidentCover {
    std::vector<SelectedPatch> patches; // what to draw
    int missing = 0;                    // selected patches drawn by an ancestor
};

// `resident(p)` must hold for the root (level 0).
ResidentCover residentCover(const Selection& selection, const PyramidGeometry& geometry,
                            const std::function<bool(PatchId)>& resident);

} // namespace ridge::lod
