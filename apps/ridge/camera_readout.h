#pragma once
// What the viewer's overlay says about the camera, GL-free so that tests can read it: the
// position in each coordinate frame it has, each line labelled with its frame (the terrain's
// local metres are not an easting/northing), and the fly speed, which follows the height
// above the ground.
#include "ridge/archive/archive_reader.h"
#include "ridge/pipeline/terrain_georeference.h"

#include <glm/vec3.hpp>

#include <optional>
#include <string>
#include <vector>

namespace ridge::cli {

class CameraReadout {
  public:
    // Fly speed per metre of height above the ground, per second (speed = rate · height):
    // the default, and the range the mouse wheel moves it in.
    static constexpr double kDefaultSpeedRate = 0.25;
    static constexpr double kMinSpeedRate = 0.01, kMaxSpeedRate = 20.0;
    // Below this height (and under the ground) the speed is that of this height.
    static constexpr double kMinSpeedHeightMetres = 2.0;

    // Reads the archive's georeference and its CRS's name (PROJ) once.
    explicit CameraReadout(const archive::ArchiveReader& reader);

    // The camera at terrain-frame `position` (metres: x east of the first column, y north of
    // the last row, z elevation; the frame `render --camera` takes):
    //   "terrain frame: x 12345.0, y 6789.0, z 5400.0 m"
    //   "WGS 84 / UTM zone 45N (EPSG:32645): E 492345.10 m, N 3092345.00 m"  (projected CRS)
    //   "NAD27 (EPSG:4267): 46.700000° N, 121.500000° W"                      (geographic CRS)
    //   "WGS 84: 27.988123° N, 86.925012° E"  (through PROJ; a CRS that is WGS 84's own
    //                                          lon/lat has this line alone, labelled with it)
    // A frame the archive lacks (no geotransform, no CRS) or a point PROJ cannot convert has
    // no line.
    std::vector<std::string> positionLines(glm::dvec3 position) const;

    // The fly speed, m/s, at `height_above_ground_m` (any finite value; under the ground
    // counts its depth) for `rate` (per second, clamped to [kMinSpeedRate, kMaxSpeedRate]).
    static double flySpeed(double height_above_ground_m, double rate);

  private:
    TerrainGeoreference georeference_;
    std::string crs_label_;          // "WGS 84 / UTM zone 45N (EPSG:32645)"; empty without a CRS
    bool wgs84_lon_lat_crs_ = false; // the CRS's x, y already are WGS 84 lon/lat
};

} // namespace ridge::cli
