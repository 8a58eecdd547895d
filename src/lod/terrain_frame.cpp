#include "ridge/lod/terrain_frame.h"

#include <algorithm>

namespace ridge::lod {

Box TerrainFrame::patchBox(PatchId p, double min_z, double max_z) const
{
    const double span = double(geometry_.cells()) * double(geometry_.step(p.level));
    const double c0 = p.x * span, c1 = std::min(c0 + span, double(geometry_.width() - 1));
    const double r0 = p.y * span, r1 = std::min(r0 + span, double(geometry_.height() - 1));
    // Rows grow southwards and y northwards: the last row is the box's south side.
    return Box{{xOf(c0), yOf(r1), min_z}, {xOf(c1), yOf(r0), max_z}};
}

} // namespace ridge::lod
