#pragma once
// The shading map (internal to ridge_render): per texture-array slot, the 8 × 8 shading tiles
// of lod::shadingTiles — which resident patch a drawn patch's fragments shade from — in the
// shader storage buffer terrain.frag reads (binding 4). Rewritten each frame for the slots
// drawn, from what is resident then; only the slots whose tiles changed are sent.
#include "ridge/gpu/gl_objects.h"
#include "ridge/lod/patch_quadtree.h"
#include "ridge/lod/patch_residency.h"
#include "ridge/lod/shading_tiles.h"

#include <cstddef>
#include <vector>

namespace ridge::render {

class ShadingMap {
  public:
    // Tiles for `slots` slots, every one the drawn patch itself.
    explicit ShadingMap(int slots);

    // The tiles of every patch of `drawn` (resident in `residency`) from what is resident now
    // (`detail`: texture detail on; off, each patch shades from itself alone). Returns the
    // bytes sent.
    size_t update(const std::vector<lod::SelectedPatch>& drawn,
                  const lod::PatchResidency& residency, const PyramidGeometry& geometry,
                  bool detail);
    // Binds the buffer to shader storage binding 4.
    void bind() const;

  private:
    gpu::GlBuffer buffer_;
    std::vector<uint32_t> tiles_; // the buffer's contents
    lod::ShadingTiles scratch_{};
};

} // namespace ridge::render
