#pragma once
// How far down each patch's vertical skirts must reach (Ulrich's skirts, as the
// hardware-tessellation paper uses them) so that every seam between selected patches is
// covered, without the kilometre-long walls a single terrain-wide depth would give.
//
// Along a seam between patches P and Q, both drawn surfaces lie within their deviation
// bounds of the finest data at every finest sample, |h_P − h| <= Λ_max(P), and all three are
// linear along the seam between finest samples. So h_P − h_Q <= Λ_max(P) + Λ_max(Q) anywhere on
// the seam, and a skirt hanging this far below P's border covers every gap where P is the
// higher side:
//
//   depth(P) = Λ_max(P) + max(Λ_max(Q) for every selected Q sharing a seam with P) + margin
//
// with Λ_max(P) = Err(P) + max over blocks and d of λ^(d) (all the tessellator may drop) and
// margin for float rounding. The skirt's foot follows its top at that depth: a short wall, not
// one hanging to the terrain's lowest point.
#include "ridge/lod/patch_quadtree.h"

#include <functional>
#include <vector>

namespace ridge::lod {

// Skirt depths (metres below the patch border) for `selected`, in the same order.
// `max_deviation(p)` returns Λ_max of a selected patch.
std::vector<double> skirtDepths(const PatchQuadtree& tree, const std::vector<PatchId>& selected,
                                const std::function<double(PatchId)>& max_deviation, double margin);

// The selected patches that share a seam (a border segment of positive length) with
// `selected[i]`; indices into `selected`.
std::vector<size_t> seamNeighbours(const PatchQuadtree& tree, const std::vector<PatchId>& selected,
                                   size_t i);

} // namespace ridge::lod
