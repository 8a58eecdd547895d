#include "ridge/lod/camera_path.h"

#include "ridge/core/error.h"
#include "ridge/core/line_reader.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <random>
#include <sstream>

namespace ridge::lod {
namespace {

// Low along the diagonal from the south-west to the north-east corner, looking ahead and
// down, bouncing back at the ends.
CameraPose flyover(const TerrainFrame& f, const std::function<double(double, double)>& ground,
                   const CameraPathSettings& s, double distance)
{
    const glm::dvec2 a(0.05 * f.extentX(), 0.05 * f.extentY()),
        b(0.95 * f.extentX(), 0.95 * f.extentY());
    const double length = glm::length(b - a);
    double t = std::fmod(distance, 2.0 * length);
    const bool back = t > length;
    t = back ? 2.0 * length - t : t;
    const glm::dvec2 dir = (back ? a - b : b - a) / length;
    const glm::dvec2 xy = a + (b - a) * (t / length);
    const double z = ground(xy.x, xy.y) + s.height_above_ground;
    const glm::dvec2 ahead = xy + dir * (10.0 * s.height_above_ground);
    return {{xy.x, xy.y, z}, {ahead.x, ahead.y, ground(ahead.x, ahead.y)}};
}

// A circle around the terrain centre at a third of its size, looking at the centre.
CameraPose orbit(const TerrainFrame& f, double min_h, double max_h, const CameraPathSettings&,
                 double distance)
{
    const glm::dvec2 c(0.5 * f.extentX(), 0.5 * f.extentY());
    const double r = 0.35 * std::max(f.extentX(), f.extentY());
    const double angle = distance / r;
    const double z = max_h + 0.25 * r;
    return {{c.x + r * std::cos(angle), c.y + r * std::sin(angle), z},
            {c.x, c.y, 0.5 * (min_h + max_h)}};
}

constexpr size_t kMaxCameraPathLineBytes = 4096;
constexpr uint64_t kMaxCameraPathFileBytes = 64u << 20;

struct FilePose {
    CameraPose pose;
    bool lon_lat = false; // given as longitude/latitude (placed by from_lon_lat already)
};

std::vector<FilePose> fromFile(const std::string& path, const CameraPathSettings& settings)
{
    // Bounded: a pose is a short line, a path a few MB (/dev/zero is one endless line).
    LineReader in(path, kMaxCameraPathLineBytes, kMaxCameraPathFileBytes);
    std::vector<FilePose> poses;
    while (const std::optional<LineReader::Line> read = in.next()) {
        const std::string& line = read->text;
        const int64_t number = read->number;
        if (read->too_long)
            throw Error(path + ":" + std::to_string(number) + ": longer than " +
                        std::to_string(kMaxCameraPathLineBytes) +
                        " bytes: not a camera path file (one pose a line)");
        if (line.empty() || line[0] == '#')
            continue;
        std::istringstream fields(line);
        CameraPose p;
        const std::string where = path + ":" + std::to_string(number);
        const bool lon_lat = line.rfind("lonlat", 0) == 0;
        std::string keyword, extra;
        if (lon_lat)
            fields >> keyword;
        if (!(fields >> p.position.x >> p.position.y >> p.position.z >> p.look_at.x >>
              p.look_at.y >> p.look_at.z) ||
            (fields >> extra))
            throw Error(where + (lon_lat ? ": expected lonlat and 6 numbers: lon lat height "
                                           "look-lon look-lat look-height"
                                         : ": expected 6 numbers: x y z look-x look-y look-z"));
        if (lon_lat) {
            if (!settings.from_lon_lat)
                throw Error(where + ": a longitude/latitude pose, but this path has no "
                                    "geographic conversion (a georeferenced archive is needed)");
            try {
                p.position = settings.from_lon_lat(p.position.x, p.position.y, p.position.z);
                p.look_at = settings.from_lon_lat(p.look_at.x, p.look_at.y, p.look_at.z);
            } catch (const Error& e) {
                throw Error(where + ": " + e.what());
            }
        }
        const double coordinates[6] = {p.position.x, p.position.y, p.position.z,
                                       p.look_at.x,  p.look_at.y,  p.look_at.z};
        if (!std::all_of(std::begin(coordinates), std::end(coordinates),
                         [](double c) { return kCameraCoordinateRange.contains(c); }))
            throw Error(path + ":" + std::to_string(number) + ": every coordinate must be " +
                        kCameraCoordinateRange.describe() + " metres");
        if (glm::length(p.look_at - p.position) <= 0.0)
            throw Error(path + ":" + std::to_string(number) +
                        ": the camera looks at its own position");
        poses.push_back({p, lon_lat});
    }
    if (poses.empty())
        throw Error(path + ": no camera poses in the file");
    return poses;
}

} // namespace

void CameraPathSettings::validate() const
{
    checkParameter("path speed_mps", speed_mps, kSpeedMpsRange);
    checkParameter("path frame_seconds", frame_seconds, kFrameSecondsRange);
    checkParameter("path height_above_ground", height_above_ground, kHeightAboveGroundRange);
    checkParameter("path teleport_every", int64_t{teleport_every}, 0, kMaxFrames);
}

std::vector<CameraPose> makeCameraPath(const TerrainFrame& frame, double min_height,
                                       double max_height,
                                       const std::function<double(double, double)>& ground,
                                       const CameraPathSettings& s, int frames)
{
    s.validate();
    checkParameter("path frames", int64_t{frames}, 0, CameraPathSettings::kMaxFrames);
    const double heights[2] = {min_height, max_height};
    checkParameters("terrain height range (m)", heights, 2, ValueRange::any());
    std::vector<CameraPose> out;
    // On a globe the paths run in the grid's metric coordinates (x, y as on the plane, z a
    // height) and are placed through the frame; lon/lat poses come placed already.
    auto placed = [&frame](CameraPose p, bool already) {
        if (!frame.onEllipsoid() || already)
            return p;
        for (glm::dvec3* q : {&p.position, &p.look_at})
            *q = frame.worldOf(frame.columnOf(q->x), frame.rowOf(q->y), q->z);
        return p;
    };
    if (s.kind != "flyover" && s.kind != "orbit" && s.kind != "teleport") {
        const std::vector<FilePose> file = fromFile(s.kind, s);
        for (int k = 0; k < frames; ++k) {
            const FilePose& f = file[size_t(k) % file.size()];
            out.push_back(placed(f.pose, f.lon_lat));
        }
        return out;
    }
    std::mt19937 rng(12345); // teleports: the same jumps every run
    std::uniform_real_distribution<double> u(0.05, 0.95);
    double offset = 0.0;
    for (int k = 0; k < frames; ++k) {
        const double distance = s.speed_mps * s.frame_seconds * k;
        if (s.kind == "orbit") {
            out.push_back(placed(orbit(frame, min_height, max_height, s, distance), false));
            continue;
        }
        if (s.kind == "teleport" && s.teleport_every > 0 && k % s.teleport_every == 0)
            offset = u(rng) * 4.0 * (frame.extentX() + frame.extentY());
        out.push_back(placed(flyover(frame, ground, s, distance + offset), false));
    }
    return out;
}

} // namespace ridge::lod
