#pragma once
// `ridge extract`: one level (or a window of it) back to a georeferenced GeoTIFF.
#include "ridge/core/progress.h"

#include <optional>
#include <string>

namespace ridge {

struct ExtractWindow {
    int x = 0, y = 0, width = 0, height = 0; // level sample units
};

struct ExtractOptions {
    static constexpr int kMaxLevel = 62; // PatchId levels; -1 means the finest

    int level = -1;                       // -1: the finest level
    std::optional<ExtractWindow> window;  // default: the level's whole valid extent
    // The value written where the archive keeps nodata (and declared as the band's nodata).
    // Unset: the source's declared nodata when it had a finite one, else NaN. Must be NaN or
    // a finite number, and not equal to any exported height.
    std::optional<double> nodata;
    Progress progress;

    // Throws ridge::Error naming the first field outside its range: level in [-1, kMaxLevel],
    // window x, y >= 0 and width, height >= 1 (whether they fit the level is checked against
    // the archive).
    void validate() const;
};

// Writes a Float32 GeoTIFF in metres; samples the archive keeps as nodata (validity masks,
// io::VoidFill) are written as the nodata value, which the band declares whenever the
// window holds any. The geotransform is the source's, scaled by the level's
// step and shifted so that every output pixel centre sits on its finest-grid sample's centre.
// Throws ridge::Error (options are validated first); leaves nothing at `output` on failure.
void extractLevel(const std::string& archive_path, const std::string& output,
                  const ExtractOptions& options);

} // namespace ridge
