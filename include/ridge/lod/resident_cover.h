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
    // What to draw, by patch index (coarse first). An ancestor standing in for several
    // selected patches carries the largest of their Err_Scr and the least certain visibility.
    std::vector<SelectedPatch> patches;
    int missing = 0; // selected patches drawn by an ancestor
};

// `resident(p)` must hold for the root (level 0).
ResidentCover residentCover(const Selection& selection, const PyramidGeometry& geometry,
                            const std::function<bool(PatchId)>& resident);
// The same into `out`, whose capacity is kept: once it has grown to the selection's size a
// call allocates nothing (the streaming planner calls it every frame).
void residentCover(const Selection& selection, const PyramidGeometry& geometry,
                   const std::function<bool(PatchId)>& resident, ResidentCover& out);

} // namespace ridge::lod
