#pragma once
// Per-instance records of the terrain draw (internal to ridge_render): one per selected
// patch, ordered front to back with whole patches first, each with its skirt depth and its
// texture-array slot. Plain C++: what goes into the instance buffer, testable without GL.
#include "ridge/lod/arrival_blend.h"
#include "ridge/lod/patch_quadtree.h"

#include <glm/vec3.hpp>

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

namespace ridge::render {

// std430 mirror of PatchInstance in shaders/terrain_common.glsl.
struct GpuPatchInstance {
    int32_t origin[2]; // finest column, row of sample (0, 0) relative to the camera anchor
    int32_t step;      // finest samples per patch cell
    float morph;       // geomorph: t towards the parent's surface (0 for other schemes)
    int32_t layer;     // texture-array slot
    int32_t level;
    float err;         // Err(P), metres
    float skirt_depth; // metres below the patch border
    // Level cells of the patch's surface along i, j (PyramidGeometry::validExtentX/Y), possibly
    // fractional: it ends on the terrain's last column and row. >= C: nothing to clip there.
    float valid_extent[2];
    float min_z; // camera-relative bounds of the patch's heights
    float max_z;
    // Cells along i, j before which the surface is dropped: 0 for a patch (nothing of it lies
    // west or north of the terrain); a clipmap footprint's cells west or north of it. The
    // terrain's first column and row are grid lines of every level, so nothing is cut there.
    float valid_start[2];
    // A patch fading in over the surface drawn before it arrived (lod/arrival_blend.h): the
    // chain of ancestors (nearest first), each with its sample (0, 0) like `origin`, its
    // finest samples per cell, its slot and its link's weight; fade_weight[0] 0: no fade (the
    // shaders then read no ancestor), and the chain ends at the first weight 0.
    int32_t fade_origin[lod::ArrivalBlend::kMaxDepth][2];
    int32_t fade_step[lod::ArrivalBlend::kMaxDepth];
    int32_t fade_layer[lod::ArrivalBlend::kMaxDepth];
    float fade_weight[lod::ArrivalBlend::kMaxDepth];
    // 1: this patch stands in for missing descendants (streaming with fades): drawn at its
    // full grid by schemes that otherwise draw coarser, so arrivals fade from what was drawn.
    int32_t stand_in;
    int32_t pad;
};
static_assert(sizeof(GpuPatchInstance) == 144, "must match the std430 layout of PatchInstance");

// The finest sample nearest the camera. Vertices are placed by their integer offset from it
// through the terrain frame (shaders/terrain_common.glsl's framePoint), so they depend only
// on the sample, never on the patch, and are exact where it matters: near the camera.
struct CameraAnchor {
    int64_t column = 0, row = 0;
    double x_rel = 0.0, y_rel = 0.0; // plane: camera-relative x, y of the anchor sample
    // Heights reach the GPU relative to this (TerrainFrame::referenceHeight of the camera).
    double height = 0.0;
    // Globe: the camera's column and row less the anchor sample's (within ±½), and its
    // longitude and latitude (radians): positions are offsets from the camera itself.
    double column_fraction = 0.0, row_fraction = 0.0;
    double longitude = 0.0, latitude = 0.0;
    glm::dvec3 camera{0.0}; // the camera position it was formed for
};
CameraAnchor cameraAnchor(const lod::TerrainFrame& frame, glm::dvec3 camera_position);

// The fade of a drawn patch this frame (lod::ArrivalBlend), each ancestor with its slot
// (the chain cut at the first that is not resident).
struct InstanceBlend {
    lod::ArrivalBlend chain;
    std::array<int, lod::ArrivalBlend::kMaxDepth> slots{};
};

struct PatchInstances {
    std::vector<GpuPatchInstance> records;
    std::vector<PatchId> patches; // per record
    // [0, whole) are whole patches; [whole, whole + partial) reach past the valid extent
    // (the clipping draw takes those).
    size_t whole = 0, partial = 0;
    // The last whole_fading of the whole patches and the last partial_fading of the others
    // fade in (fade_weight[0] > 0; groupFadingLast): only they are drawn with the programs
    // that read ancestors, which cost every vertex they run on (docs/PERF.md, "Arrivals that
    // fade in").
    size_t whole_fading = 0, partial_fading = 0;
    size_t total() const { return whole + partial; }
};

// One draw's share of PatchInstances: records [first, first + count), clipped at the valid
// extent or not, fading in or not.
struct InstanceGroup {
    size_t first = 0, count = 0;
    bool clipped = false, fading = false;
};
// The four groups in draw order: whole, whole fading, clipped, clipped fading (empty ones
// included).
std::array<InstanceGroup, 4> instanceGroups(const PatchInstances& instances);

// Moves the fading records of each group (whole, clipped) after the others of that group,
// keeping the order within each (front to back), and counts them.
void groupFadingLast(PatchInstances& instances);

// Records for `selection` seen from `camera_position`. `slot_of(p)` is the resident slot of
// a selected patch, `lambda_max(p)` the largest λ^(d) of its blocks (metres). With an
// `exaggeration` k (SelectionSettings::exaggeration) the camera is in the exaggerated space
// and every vertical quantity is k times the archive's: bounds, Err(P), λ and so the skirts.
PatchInstances
buildPatchInstances(const lod::PatchQuadtree& tree, const lod::Selection& selection,
                    glm::dvec3 camera_position, const std::function<int(PatchId)>& slot_of,
                    const std::function<double(PatchId)>& lambda_max, double skirt_margin,
                    double exaggeration = 1.0,
                    const std::function<std::optional<InstanceBlend>(PatchId)>& blend_of = {});

} // namespace ridge::render
