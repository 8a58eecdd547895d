#pragma once
// How far down each patch's vertical skirts must reach (Ulrich's skirts, as the
// hardware-tessellation paper uses them) so that every seam between selected patches is
// covered, without the kilometre-long walls a single terrain-wide depth would give.
//
// Along a seam between patches P and Q, both drawn surfaces lie within their deviation
// bounds Λ_max of the finest data, which is >= min_height(P) there (min_height covers P and
// its descendants). So Q's surface on the seam is >= min_height(P) − Λ_max(Q) − margin, and a
// skirt of P reaching that low covers any gap where P is the higher side:
//
//   foot(P) = min_height(P) − max(Λ_max(P), Λ_max(Q) for every selected Q sharing a seam) − margin
//
// with Λ_max(P) = Err(P) + max over blocks and d of λ^(d) (what the tessellator may drop) and
// margin = the finest level's codec and quantization error (the data min_height describes).
#include "ridge/lod/patch_quadtree.h"

#include <functional>
#include <vector>

namespace ridge::lod {

// Skirt foot heights (terrain frame, metres) for `selected`, in the same order.
// `max_deviation(p)` returns Λ_max of a selected patch.
std::vector<double> skirtFeet(const PatchQuadtree& tree, const std::vector<PatchId>& selected,
                              const std::function<double(PatchId)>& max_deviation, double margin);

// The selected patches that share a seam (a border segment of positive length) with
// `selected[i]`; indices into `selected`.
std::vector<size_t> seamNeighbours(const PatchQuadtree& tree, const std::vector<PatchId>& selected,
                                   size_t i);

} // namespace ridge::lod
