#pragma once
// What a codec is told about patch `id` of a pyramid (PatchContext): its place in the
// quadtree, the samples that cover the level's valid extent (those a surface is cut from:
// coveredCells + 1 per axis; progressive v2 codes only them), its parent's reconstruction.
// The build, the archive reader and the GPU decoder all derive it here, so they agree.
#include "ridge/codec/height_codec.h"
#include "ridge/pyramid/pyramid_geometry.h"

namespace ridge {

inline PatchContext patchContext(const PyramidGeometry& g, PatchId id, const uint16_t* parent)
{
    return {g.patchSize(),          id.level, parent, id.childIndex(), g.coveredCellsX(id) + 1,
            g.coveredCellsY(id) + 1};
}

} // namespace ridge
