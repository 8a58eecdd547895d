#pragma once
// `ridge hillshade`: a shaded-relief picture of one level.
#include "ridge/core/height_grid.h"
#include "ridge/core/parameter_check.h"
#include "ridge/core/progress.h"

#include <cstdint>
#include <string>
#include <vector>

namespace ridge {

struct HillshadeOptions {
    // Light azimuth either way round up to a full turn; altitude from the horizon to the
    // zenith (gdaldem's ranges); exaggeration positive and short of flattening every slope
    // to a cliff.
    static constexpr ValueRange kAzimuthDegreesRange = ValueRange::closed(-360.0, 360.0);
    // (0, 90] as render's sun (render::kSunAltitudeDegreesRange): at 0 the sun lies on the
    // horizon and shades nothing, which both refuse.
    static constexpr ValueRange kAltitudeDegreesRange = ValueRange::openClosed(0.0, 90.0);
    static constexpr ValueRange kZFactorRange = ValueRange::openClosed(0.0, 1e6);
    static constexpr int kMaxLevel = 62; // PatchId levels; -1 means the finest

    int level = -1;         // -1: finest level
    double azimuth = 315.0; // light from the north-west, degrees clockwise from north
    double altitude = 45.0; // degrees above the horizon
    double z_factor = 1.0;  // vertical exaggeration
    bool colour = true;     // hypsometric tint under the shading; false = grey like gdaldem
    Progress progress;

    // Throws ridge::Error naming the first field outside its range above (NaN included).
    void validate() const;
};

// Horn's (1981) slope/aspect on metres with the level's ground spacing, the same formula as
// gdaldem hillshade. Returns width*height*(colour ? 3 : 1) bytes, row-major.
// With `valid` (1 = data, width*height entries, non-empty) the result is RGBA (4 bytes per
// pixel): nodata pixels are transparent background (0, 0, 0, 0), the others opaque; Horn's
// window reads the centre height in place of a nodata neighbour (no slope towards heights
// that are not there) and the tint's range covers the valid samples only.
// `water`: null paints water by the height rule of archives without sample flags
// (palette::isWater); else the pixels where it holds kSampleWater are water (empty: none).
std::vector<uint8_t> shadeRelief(const std::vector<float>& metres, int width, int height,
                                 double spacing_x, double spacing_y,
                                 const HillshadeOptions& options,
                                 const std::vector<uint8_t>& valid = {},
                                 const std::vector<uint8_t>* water = nullptr);

// Decodes the level and writes the picture as PNG (RGBA with transparent nodata when the
// archive keeps nodata in that level, else RGB or grey). Throws ridge::Error (options are
// validated first; shadeRelief validates them too).
void writeHillshade(const std::string& archive_path, const std::string& output,
                    const HillshadeOptions& options);

} // namespace ridge
