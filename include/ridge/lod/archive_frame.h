#pragma once
// Which terrain frame an archive is drawn in (lod/terrain_frame.h), from its stored
// georeference: the plane every archive was drawn on before the globe, or the WGS 84
// ellipsoid. PROJ (through io) turns the archive's datum into WGS 84.
#include "ridge/lod/terrain_frame.h"

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace ridge::archive {
class ArchiveReader;
}

namespace ridge::lod {

enum class FrameChoice {
    Auto,      // the ellipsoid for a raster that goes round the Earth, else the plane
    Plane,     // the archive's local metric frame
    Ellipsoid, // the WGS 84 ellipsoid (a georeferenced geographic or projected raster)
};
// "auto", "plane", "ellipsoid".
std::string_view frameChoiceName(FrameChoice c);
// nullopt for anything else.
std::optional<FrameChoice> parseFrameChoice(std::string_view name);

// The columns in 360° when `reader`'s grid goes round the Earth (geographic, north-up, its
// columns spanning a whole turn, column 0 repeated or not), else 0. The rule terrainFrameOf
// wraps by, without PROJ (the datum's shift of metres does not change the period).
int64_t wrapColumnsOf(const archive::ArchiveReader& reader);

// The frame of `reader` under `choice`. Throws ridge::Error naming `what` (the archive's
// path) when the ellipsoid is asked for and the archive cannot lie on it: no geotransform or
// CRS, a rotated or south-up geographic grid, samples beyond ±90° of latitude or spanning more
// than 360° of longitude, a CRS PROJ cannot relate to WGS 84, a projection that does not
// reach the raster's samples.
TerrainFrame terrainFrameOf(const archive::ArchiveReader& reader, FrameChoice choice,
                            const std::string& what);

} // namespace ridge::lod
