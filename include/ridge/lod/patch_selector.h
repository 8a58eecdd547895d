#pragma once
// How a LOD scheme chooses what to draw, GL-free: the selection policy the renderer and the
// streaming planner plug in. Two kinds exist:
//   - the screen-space-error walk of the patch quadtree (QuadtreeSelector: the hardware-
//     tessellation paper's §5, used by tess, chunked, brute and geomorph), whose missing
//     patches are drawn by their finest resident ancestor (lod::residentCover);
//   - a scheme's own selector (rings: patches by distance from the viewer, the fractal-rings
//     paper's updateRings), stateful between frames, with its own rule for what to draw while
//     some of what it wants is not resident (a rule that never puts two levels across an edge
//     its stitching cannot close).
// The planner asks the same selector for prefetch (preview(), for an extrapolated camera,
// which must not change the selector's state) and for the cover it keeps resident and draws.
#include "ridge/lod/patch_quadtree.h"
#include "ridge/lod/resident_cover.h"

#include <functional>
#include <vector>

namespace ridge::lod {

class PatchSelector {
  public:
    virtual ~PatchSelector() = default;

    // This frame's wanted patches for `camera`: what to make resident and draw when all of it
    // is (SelectedPatch::rank orders requests within a level), at most settings.max_patches.
    // May update the selector's state (rings re-centre their structure).
    virtual void select(const Camera& camera, const SelectionSettings& settings,
                        Selection& out) = 0;
    // What select() would want for `camera`, changing nothing (prefetch).
    virtual void preview(const Camera& camera, const SelectionSettings& settings,
                         Selection& out) const = 0;
    // What to draw now of `desired` (this frame's select()) given what is resident: never a
    // hole where `desired` draws, only resident patches. `resident(root)` holds. Called by
    // the planner before and after the frame's uploads; the last call decides what is drawn.
    virtual void cover(const Selection& desired, const std::function<bool(PatchId)>& resident,
                       ResidentCover& out) = 0;
};

// The screen-space-error walk (PatchQuadtree::select) and its resident cover.
class QuadtreeSelector final : public PatchSelector {
  public:
    explicit QuadtreeSelector(const PatchQuadtree& tree) : tree_(tree) {}

    void select(const Camera& camera, const SelectionSettings& settings, Selection& out) override
    {
        out = tree_.select(camera, settings);
    }
    void preview(const Camera& camera, const SelectionSettings& settings,
                 Selection& out) const override
    {
        out = tree_.select(camera, settings);
    }
    void cover(const Selection& desired, const std::function<bool(PatchId)>& resident,
               ResidentCover& out) override
    {
        residentCover(desired, tree_.geometry(), resident, out);
    }

  private:
    const PatchQuadtree& tree_;
};

} // namespace ridge::lod
