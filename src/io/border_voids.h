#pragma once
#include <cstdint>
#include <vector>

namespace ridge::io::detail {

// The voids that are not terrain: those 8-connected to the raster border (the empty collar
// of a reprojected DEM, sea, a clipping mask), as opposed to holes enclosed by data.
// `void_mask` has 0 at voids (ingest's convention); returns 1 at every void of a component
// that touches row 0, row height-1, column 0 or column width-1, 0 elsewhere, and the count in
// `kept`. Memory: the result plus a stack of at most the voids' count.
std::vector<uint8_t> borderConnectedVoids(const std::vector<uint8_t>& void_mask, int width,
                                          int height, int64_t& kept);

} // namespace ridge::io::detail
