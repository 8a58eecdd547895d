#pragma once
// `ridge hillshade`: a shaded-relief picture of one level.
#include "ridge/core/height_grid.h"
#include "ridge/core/progress.h"

#include <cstdint>
#include <string>
#include <vector>

namespace ridge {

struct HillshadeOptions {
    int level = -1;          // -1: finest level
    double azimuth = 315.0;  // light from the north-west, degrees clockwise from north
    double altitude = 45.0;  // degrees above the horizon
    double z_factor = 1.0;   // vertical exaggeration
    bool colour = true;      // hypsometric tint under the shading; false = grey like gdaldem
    Progress progress;
};

// Horn's (1981) slope/aspect on metres with the level's ground spacing, the same formula as
// gdaldem hillshade. Returns width*height*(colour ? 3 : 1) bytes, row-major.
std::vector<uint8_t> shadeRelief(const std::vector<float>& metres, int width, int height,
                                 double spacing_x, double spacing_y, const HillshadeOptions& options);

// Decodes the level and writes the picture as PNG. Throws ridge::Error.
void writeHillshade(const std::string& archive_path, const std::string& output,
                    const HillshadeOptions& options);

} // namespace ridge
