#pragma once
// Deterministic camera paths over a terrain for benchmarks (`ridge bench --path`): the same
// frames every run, timed by a fixed simulated frame interval, so frame-time figures compare
// renderers and settings rather than camera luck.
#include "ridge/core/height_grid.h"
#include "ridge/lod/camera.h"
#include "ridge/lod/terrain_frame.h"

#include <functional>
#include <string>
#include <vector>

namespace ridge::lod {

struct CameraPose {
    glm::dvec3 position{0.0};
    glm::dvec3 look_at{0.0, 1.0, 0.0};
};

struct CameraPathSettings {
    // Along the path, m/s: up to the fly camera's top speed (1000 km/s).
    static constexpr ValueRange kSpeedMpsRange = ValueRange::openClosed(0.0, 1e6);
    // Simulated seconds per frame: up to an hour.
    static constexpr ValueRange kFrameSecondsRange = ValueRange::openClosed(0.0, 3600.0);
    // Metres above the ground: no higher than any height may be (kMaxAbsHeightMetres).
    static constexpr ValueRange kHeightAboveGroundRange =
        ValueRange::closed(0.0, kMaxAbsHeightMetres);
    static constexpr int kMaxFrames = 100000000;

    // flyover, orbit, teleport, or a file of poses, one a line: "x y z lx ly lz" in the
    // terrain frame's local metres, or "lonlat LON LAT H LLON LLAT LH" (WGS 84 degrees,
    // metres in the terrain's vertical datum, absolute), which needs from_lon_lat. On a
    // globe frame, local x, y are the grid's metric coordinates and z a height, placed
    // through the frame (TerrainFrame::worldOf), and from_lon_lat gives world points.
    std::string kind = "flyover";
    // Longitude°, latitude°, height → terrain frame (pipeline's TerrainGeoreference through
    // PROJ; lod itself knows no CRS). Throws ridge::Error for a point it cannot convert.
    std::function<glm::dvec3(double longitude, double latitude, double height)> from_lon_lat;
    double speed_mps = 250.0; // along the path
    double frame_seconds = 1.0 / 60.0;
    double height_above_ground = 300.0; // flyover, teleport
    int teleport_every = 60;            // frames between jumps (0: never)

    // Throws ridge::Error naming the first field outside its range (NaN and infinities too).
    void validate() const;
};

// `ground(x, y)` is the terrain height in metres. Throws ridge::Error for settings outside
// their ranges (validate()), `frames` outside [0, kMaxFrames], non-finite heights, an unknown
// kind or an unreadable or malformed path file (naming the file and the line; every pose must
// lie within kCameraCoordinateRange).
std::vector<CameraPose> makeCameraPath(const TerrainFrame& frame, double min_height,
                                       double max_height,
                                       const std::function<double(double, double)>& ground,
                                       const CameraPathSettings& settings, int frames);

} // namespace ridge::lod
