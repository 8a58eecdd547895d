#pragma once
// Deterministic camera paths over a terrain for benchmarks (`ridge bench --path`): the same
// frames every run, timed by a fixed simulated frame interval, so frame-time figures compare
// renderers and settings rather than camera luck.
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
    std::string kind = "flyover"; // flyover, orbit, teleport, or a file of "x y z lx ly lz" lines
    double speed_mps = 250.0;     // along the path
    double frame_seconds = 1.0 / 60.0;
    double height_above_ground = 300.0; // flyover, teleport
    int teleport_every = 60;            // frames between jumps
};

// `ground(x, y)` is the terrain height in metres. Throws ridge::Error for an unknown kind or
// an unreadable or malformed path file (naming the file and the line).
std::vector<CameraPose> makeCameraPath(const TerrainFrame& frame, double min_height,
                                       double max_height,
                                       const std::function<double(double, double)>& ground,
                                       const CameraPathSettings& settings, int frames);

} // namespace ridge::lod
