#pragma once
// Guaranteed patch error bounds ("Calculating Guaranteed Patch Error Bound",
// Yusov & Shevtsov 2011, §4; the recursion is ROAM's nested wedgie thickness,
// Duchaineau et al. 1997).
//
//   Err_Appr(P at finest level) = 0
//   Err_Appr(P) = Err_Int(P) + max over children C of Err_Appr(C)
//   Err(P)      = Err_Appr(P) + δ_l                          (δ_l: codec bound at level l)
//
// Err_Int(P) is the largest deviation of P's interpolated surface from its children's
// samples. We take, at every child sample, the largest deviation from the parent cell's
// bilinear interpolant and from both of its triangulations (either diagonal), so the bound
// holds for a bilinear renderer and for a triangulating one whatever diagonal it picks
// consistently: the difference of two such surfaces is bilinear (or linear) on each child
// cell (triangle), so its maximum is reached at child samples. By induction Err_Appr(P)
// bounds |surface(P) - h_finest| at every full-resolution sample P covers.
//
// Only child samples whose cells touch the valid extent are considered: padding is never
// drawn, so its deviation does not matter.
#include "ridge/pyramid/level_pyramid.h"

#include <vector>

namespace ridge {

// Err_Int of patch p (level p.level < finest) in code units.
double interpolationError(const LevelView& parent, const LevelView& child, int patch_size,
                          PatchId p);
// Same, for a caller that already holds p's samples (patch_size^2, as extractPatch gives them).
double interpolationError(const uint16_t* parent_samples, const LevelView& child, int patch_size,
                          PatchId p);

// Per-patch values for every patch of the pyramid, indexed by geometry.patchIndex().
struct PatchErrors {
    std::vector<float> err_int;  // code units; 0 at the finest level
    std::vector<float> err_appr; // code units
    // Range of the patch's own samples and of all its descendants' samples, so that a
    // bounding box built from it is safe for hierarchical culling (a decimated parent's own
    // samples can miss a child's peak).
    std::vector<uint16_t> min_code;
    std::vector<uint16_t> max_code;
};

// PatchErrors for every patch of `geometry`, zero-initialised.
PatchErrors makePatchErrors(const PyramidGeometry& geometry);

// Err_Int (below the pyramid's finest level) and the own sample range of every patch of
// levels [first_level, last_level] of `pyramid`, in parallel over patches. `errors` may belong
// to a deeper geometry whose levels 0..finest coincide with the pyramid's (streaming build).
void measurePatches(const LevelPyramid& pyramid, int first_level, int last_level,
                    PatchErrors& errors);

// The recursion, from level `final_level - 1` up to 0: Err_Appr = Err_Int + max over children,
// ranges widened by the children's. Levels >= final_level must already hold final values.
void accumulatePatchErrors(const PyramidGeometry& geometry, int final_level, PatchErrors& errors);

// All of the above for an in-memory pyramid: Err_Appr = 0 at the finest level.
// Cost: one pass over every sample of every level.
PatchErrors computePatchErrors(const LevelPyramid& pyramid);

} // namespace ridge
