#pragma once
// Coarse LOD: the unbalanced patch quad tree of the hardware-tessellation paper (§5).
//
// Each frame the tree is walked from the root: a patch whose bounding box is outside the view
// frustum is dropped with its subtree; a patch is drawn when Err_Scr(P) <= ε or it is a leaf
// of the archive, otherwise its existing children are visited. The selected patches tile the
// visible part of the valid extent without overlap, so fine LOD (tessellation) and skirts see
// a partition. Texture detail is walked apart, below the drawn patches (Selection::detail):
// it decides what is resident for shading, never what is drawn. Plain C++: no GL, cheap (a few µs
// per hundred patches), thread-compatible.
#include "ridge/lod/camera.h"
#include "ridge/lod/frustum.h"
#include "ridge/lod/horizon.h"
#include "ridge/lod/terrain_frame.h"

#include <cstdint>
#include <limits>
#include <vector>

namespace ridge::archive {
class ArchiveReader;
}

namespace ridge::lod {

// What selection needs of a patch, from the archive index: metres, conservative.
struct PatchBounds {
    float min_height = 0.f; // covers the patch and its descendants
    float max_height = 0.f;
    float err = 0.f; // Err(P): guaranteed vertical error against the finest data
};

struct SelectionSettings {
    // ε may be 0 (brute force: the finest level wherever the frustum lets it); the upper end
    // only keeps ε and its 25% raises finite.
    static constexpr ValueRange kEpsilonPxRange = ValueRange::closed(0.0, 1e9);
    // error_scale: Ulrich's chunks reach 1 + their largest tolerance (src/render/schemes/).
    static constexpr ValueRange kErrorScaleRange = ValueRange::closed(1.0, 1000.0);

    double epsilon_px = 2.0; // ε, pixels
    // Texture detail, decoupled from geometry: below each drawn patch, the descendants whose
    // level's projected sample spacing (lod::projectedSampleSpacing) is at most this many
    // pixels — or kShadingDepth levels below it, or the finest level — are wanted resident
    // (Selection::detail), so that fragments shade from height and normal maps of about one
    // texel per pixel while the drawn patches stay geometry's (ε alone). 0 disables.
    static constexpr ValueRange kTexelPxRange = ValueRange::closed(0.0, 1e9);
    double texel_px = 0.0;
    bool cull = true; // view-frustum (and, on a whole-Earth globe, horizon) culling of boxes
    // ρ in Err_Scr: the box depth bound that holds off-axis (visibleDepthBound), or the
    // paper's distance to the closest box point (false; under-refines at screen corners).
    bool conservative_distance = true;
    // With conservative_distance: visibleDepthBound's side-on factor (see there).
    bool side_on = true;
    // At most this many patches, drawn and detail together; when the tree at ε needs more, ε
    // is raised by 25% steps until the drawn ones fit, then the texel target until the detail
    // fits too, and Selection::epsilon_px and texel_px say what was used.
    size_t max_patches = std::numeric_limits<size_t>::max();
    // The drawn mesh's vertical error as a multiple of Err(P): 1 for meshes of the patch's
    // own samples; 1 + k for Ulrich's chunks simplified to k·Err(P) (lod/chunk_mesh.h).
    double error_scale = 1.0;
    // The longest straight cell the drawn mesh makes, in the patch level's cells: on a globe
    // its sag below the curved surface (TerrainFrame::chordSag) is added to Err(P). 1 for
    // meshes of the patch's own samples (the tessellator accounts for its coarser blocks
    // itself); a simplified chunk's may span the patch.
    static constexpr ValueRange kStraightCellsRange = ValueRange::closed(1.0, 1e9);
    double straight_cells = 1.0;
    // Vertical exaggeration: the terrain is drawn with every height multiplied by this factor
    // (the camera lives in that space), so selection measures boxes and Err(P) there too —
    // Err_Scr of the exaggerated surface is exaggeration · Err_Scr, and ε holds on what is
    // drawn. 1: true heights.
    static constexpr ValueRange kExaggerationRange = ValueRange::closed(0.01, 100.0);
    double exaggeration = 1.0;

    // Throws ridge::Error naming the first field outside its range (max_patches must be >= 1).
    void validate() const;
};

struct SelectedPatch {
    PatchId id;
    double screen_error = 0.0; // Err_Scr(P), pixels
    Visibility visibility = Visibility::Inside;
    double texel_spacing = 0.0; // projected sample spacing of the patch's level, pixels
    // Streaming order within a level, larger first (stream::requestPriority): Err_Scr for
    // the quadtree walk; a scheme that owns its selection ranks by its own order (rings:
    // inner rings first).
    double rank = 0.0;
};

// How many levels below a drawn patch texture detail reaches (SelectionSettings::texel_px):
// 8× its sample density, which the shading map addresses as 2^3 × 2^3 tiles per drawn patch
// (ridge/lod/shading_tiles.h).
inline constexpr int kShadingDepth = 3;

struct Selection {
    std::vector<SelectedPatch> patches; // drawn: they tile the visible extent
    // Texture detail (SelectionSettings::texel_px): descendants of drawn patches, 1 to
    // kShadingDepth levels below them, that fragments shade from once resident. Their areas
    // do not overlap; a drawn patch with none has texels fine enough of its own. The streaming
    // planner requests them after every drawn patch and never lets them displace one.
    std::vector<SelectedPatch> detail;
    double epsilon_px = 0.0; // ε actually met (>= the requested one)
    double texel_px = 0.0;   // texel target actually met (raised to fit; 0: off)
    int visited = 0;         // patches tested
    int culled = 0;          // subtrees dropped by the frustum test
    // Levels a scheme's own selection was made coarser by to fit max_patches (the quadtree
    // walk raises epsilon_px instead): 0 when it fits as designed.
    int levels_coarser = 0;
};

class PatchQuadtree {
  public:
    // `bounds` indexed by geometry().patchIndex(p).
    PatchQuadtree(TerrainFrame frame, std::vector<PatchBounds> bounds);
    // The index's bounds in the archive's plane frame, or in `frame` (lod::terrainFrameOf).
    static PatchQuadtree fromArchive(const archive::ArchiveReader& reader);
    static PatchQuadtree fromArchive(const archive::ArchiveReader& reader, TerrainFrame frame);

    const TerrainFrame& frame() const { return frame_; }
    const PyramidGeometry& geometry() const { return frame_.geometry(); }
    const PatchBounds& bounds(PatchId p) const { return bounds_[geometry().patchIndex(p)]; }
    // The patch's box in the terrain frame, heights multiplied by `exaggeration`
    // (SelectionSettings::exaggeration).
    Box box(PatchId p, double exaggeration = 1.0) const;

    // Validates `settings` first (SelectionSettings::validate).
    Selection select(const Camera& camera, const SelectionSettings& settings) const;

  private:
    struct Thresholds {
        double gamma;       // γ (texture detail)
        double error_gamma; // γ · error_scale · exaggeration (Err_Scr)
        double exaggeration;
        double epsilon; // pixels
        double texel;   // pixels; 0 off
    };
    // A patch as the walk sees it: culled, or its Err_Scr and projected sample spacing.
    struct Measured {
        bool culled = false;
        Visibility visibility = Visibility::Inside;
        double err_scr = 0.0;
        double texel_scr = 0.0;
    };
    Measured measure(PatchId p, const Camera& camera, const Frustum* frustum,
                     const HorizonOccluder* horizon, const Thresholds& t,
                     const SelectionSettings& settings) const;
    void visit(PatchId p, const Camera& camera, const Frustum* frustum,
               const HorizonOccluder* horizon, const Thresholds& t,
               const SelectionSettings& settings, Selection& out) const;
    // Texture detail under drawn patch `p` (measured `m`), `depth` levels below it.
    void visitDetail(PatchId p, const Measured& m, int depth, const Camera& camera,
                     const Frustum* frustum, const HorizonOccluder* horizon, const Thresholds& t,
                     const SelectionSettings& settings, Selection& out) const;

    TerrainFrame frame_;
    std::vector<PatchBounds> bounds_;
};

} // namespace ridge::lod
