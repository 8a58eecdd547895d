#pragma once
// Bytes fetched per view: what a cold cache must read from an archive to draw one camera's
// view, counted on the renderer's own LOD selection (lod::PatchQuadtree::select, the function
// TerrainRenderer calls; no GL, no decoding). It measures a codec where a renderer pays for it
// — the blobs a view streams — rather than over the whole file.
//
// A progressive codec decodes a patch from its parent's reconstruction
// (HeightCodec::capabilities().needs_ancestors), so a cold cache reads every ancestor of each
// selected patch too, each once however many descendants share it; a codec without that need
// reads the selected patches alone. Bytes are blob sizes from the index (PatchRecord::size:
// block errors, validity mask and payload), not the index or metadata an open reads once.
//
// Thread safety: pure functions of their arguments.
#include "ridge/lod/camera.h"
#include "ridge/lod/patch_quadtree.h"

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace ridge::archive {
class ArchiveReader;
}

namespace ridge::stream {

struct ViewBytes {
    uint64_t bytes = 0;            // sum of PatchRecord::size over the patches read
    size_t patches = 0;            // distinct patches read: selected, plus ancestors if counted
    size_t selected = 0;           // patches the selection draws, and its texture detail
    bool counts_ancestors = false; // the codec declares needs_ancestors
    double epsilon_px = 0.0;       // ε the selection met (raised only under max_patches)
};

// The selection settings TerrainRenderer uses for the tessellation scheme (its default) at ε
// and texel_px (render::RenderSettings: ε 2 px, texel_px 1 by default): culling on,
// conservative ρ with the side-on factor, no patch budget (a cold view, not a slot-bound one).
lod::SelectionSettings rendererSelectionSettings(double epsilon_px, double texel_px = 1.0);

// The cold-cache bytes of `camera`'s view: quadtree.select(camera, settings), then the blob
// sizes of the selected patches and — when reader.codec().capabilities().needs_ancestors —
// of all their ancestors, each patch once. `quadtree` must be
// lod::PatchQuadtree::fromArchive(reader) (built once, reused across views).
// Throws ridge::Error for settings select refuses. Cost: the selection, O(selected · levels)
// for the ancestors and one pass over a byte per patch of the archive (patchesToFetch).
ViewBytes viewBytes(const archive::ArchiveReader& reader, const lod::PatchQuadtree& quadtree,
                    const lod::Camera& camera, const lod::SelectionSettings& settings);
// Same, building the quadtree from the reader's index (O(patches); use the overload above
// for many views).
ViewBytes viewBytes(const archive::ArchiveReader& reader, const lod::Camera& camera,
                    double epsilon_px, double texel_px = 1.0);

// The patches a cold cache reads for `selected`: each patch, and each ancestor of each when
// `with_ancestors`, once, in ascending index order (geometry().patchIndex).
std::vector<PatchId> patchesToFetch(const PyramidGeometry& geometry,
                                    const std::vector<lod::SelectedPatch>& selected,
                                    bool with_ancestors);

// Three typical views, defined from the archive's extents alone (frame extents and index
// heights: no decoding), so that every raster gets them. With W, H the terrain frame's extents
// (lod::TerrainFrame::extentX/Y), c = (W/2, H/2) its centre, z0, z1 the root patch's min and
// max heights (the whole terrain's), z_mid = (z0 + z1)/2, R = ½·sqrt(W² + H² + (z1 − z0)²) the
// radius of the terrain's bounding box, a 60° vertical field of view and clip planes
// 1 m .. 2·(R + the camera's distance to c), which hold the whole box:
//   near  — low over the centre looking at the horizon: position (c, t + 300 m), where t is
//           the max height of the finest patch under c (>= every sample there), looking north
//           (+y, grid north) 5° below the horizontal (a fly-over camera: a few hundred metres
//           up, the foreground fine, the rest fading out to the northern border).
//   mid   — an oblique view of a good part of the terrain: looking at (c, z_mid) from the south,
//           30° above the horizontal, from a distance R (half of far's: about half the terrain
//           across the picture); the camera kept at least 300 m above z1.
//   far   — the whole terrain in view from high above: looking at (c, z_mid) from the south,
//           60° above the horizontal, from a distance 2R (R / sin 30°: the bounding sphere
//           fits the vertical field of view, and 16:9 is wider), at least 300 m above z1.
// On a raster with fewer samples across than the viewport has pixels (the 1201² SRTM tile at
// 1920 × 1080), far shows every sample at a pixel or more, so it needs about the whole
// archive, more than near; far fetches less only where the terrain out-resolves the screen.
enum class TypicalView { Near, Mid, Far };
inline constexpr TypicalView kTypicalViews[] = {TypicalView::Near, TypicalView::Mid,
                                                TypicalView::Far};
inline constexpr double kNearViewHeightAboveTop = 300.0; // metres
// "near", "mid", "far".
std::string typicalViewName(TypicalView view);
// The camera of `view` for the archive `quadtree` was built from. Throws ridge::Error for a
// viewport lod::Camera refuses.
lod::Camera typicalViewCamera(const lod::PatchQuadtree& quadtree, TypicalView view,
                              lod::Viewport viewport);

} // namespace ridge::stream
