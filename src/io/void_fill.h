#pragma once
#include "ridge/core/height_grid.h"
#include "ridge/core/progress.h"

#include <cstdint>
#include <string>
#include <vector>

namespace ridge::io::detail {

// Fills the codes of `grid` where `void_mask` is 0 from the valid codes around them
// (GDALFillNodata: inverse distance weighting, then smoothing), in place. Valid codes lie in
// [min_valid_code, max_valid_code]. `void_mask` is consumed: filled samples become 255.
// Throws Error naming `path` if GDAL fails or a void is left unfilled, Cancelled if
// `progress` asks to stop.
void fillVoids(const std::string& path, CodeGrid& grid, std::vector<uint8_t>& void_mask,
               uint16_t min_valid_code, uint16_t max_valid_code, const Progress& progress);

} // namespace ridge::io::detail
