#include "ridge/pipeline/camera_placement.h"

#include "ridge/core/error.h"
#include "ridge/lod/camera.h"
#include "ridge/lod/camera_orientation.h"
#include "ridge/lod/ellipsoid.h"
#include "ridge/lod/patch_quadtree.h"

#include <cmath>
#include <numbers>
#include <utility>

namespace ridge {

namespace {

// The finest surface under local (x, y), times the exaggeration `k` it is drawn with; an error
// naming `what` off the raster.
double groundAt(HeightQuery& query, glm::dvec2 local, const char* what, double k)
{
    const HeightSample s = query.sample(local, PointSpace::Local);
    if (!s.on_raster)
        throw Error(std::string(what) + " is off the raster (pixel/line " +
                    formatNumber(s.pixel.x) + ", " + formatNumber(s.pixel.y) +
                    "): there is no ground height there");
    return k * s.height;
}

// The globe's placement (see the header); the checks above are done.
ResolvedCamera resolveOnGlobe(HeightQuery& query, const CameraPlacement& p,
                              const lod::TerrainFrame& frame)
{
    const TerrainGeoreference& geo = query.georeference();
    const lod::Ellipsoid& e = frame.geodetic().ellipsoid;
    constexpr double kDeg = std::numbers::pi / 180.0;
    // A point given either way: grid column and row (for the ground) and its world point at
    // `height` (NaN: on the ground).
    auto place = [&](const std::optional<glm::dvec3>& local,
                     const std::optional<glm::dvec3>& lonlat, const char* what) {
        glm::dvec2 grid;
        double height;
        if (local) {
            checkParameters(what, &local->x, 3, lod::kCameraCoordinateRange);
            grid = {frame.columnOf(local->x), frame.rowOf(local->y)};
            height = local->z;
        } else {
            const glm::dvec3 ll = *lonlat;
            // The query's georeference refuses an archive without a CRS, and longitudes and
            // latitudes off their ranges, by name; the frame is WGS 84 already.
            (void)geo.toLocal({ll.x, ll.y}, PointSpace::LonLat);
            const glm::dvec3 g =
                frame.gridOf(lod::geodeticToEcef(e, ll.x * kDeg, ll.y * kDeg, 0.0));
            grid = {g.x, g.y};
            height = ll.z;
        }
        return std::pair<glm::dvec2, double>(grid, height);
    };
    auto ground = [&](glm::dvec2 grid, const char* what) {
        return groundAt(query, {frame.xOf(grid.x), frame.yOf(grid.y)}, what, p.exaggeration);
    };
    ResolvedCamera out;
    if (p.position || p.position_lonlat) {
        auto [grid, height] = place(p.position, p.position_lonlat, "camera position");
        checkParameter("camera height (m)", height, lod::kCameraCoordinateRange);
        if (p.above_ground)
            height += ground(grid, "the camera position");
        const glm::dvec3 position = frame.worldOf(grid.x, grid.y, height);
        checkParameters("camera position", &position.x, 3, lod::kCameraCoordinateRange);
        out.position = position;
        if (p.heading_deg) {
            // Heading from true north, pitch above the horizon, in the local frame there.
            const glm::dvec3 d = lod::headingPitchDirection(*p.heading_deg, *p.pitch_deg);
            out.look_at = position + 1000.0 * (frame.basisAt(grid.x, grid.y).matrix() * d);
        }
    }
    if (p.look_at || p.look_at_lonlat) {
        auto [grid, height] = place(p.look_at, p.look_at_lonlat, "look-at point");
        if (std::isnan(height))
            height = ground(grid, "the look-at point");
        checkParameter("look-at height (m)", height, lod::kCameraCoordinateRange);
        out.look_at = frame.worldOf(grid.x, grid.y, height);
    }
    return out;
}

} // namespace

ResolvedCamera resolveCameraPlacement(HeightQuery& query, const CameraPlacement& p,
                                      const lod::TerrainFrame* frame)
{
    if (p.position && p.position_lonlat)
        throw Error("camera position given both in local metres and as longitude/latitude: "
                    "give one");
    if (p.look_at && p.look_at_lonlat)
        throw Error("look-at point given both in local metres and as longitude/latitude: give "
                    "one");
    const bool look_at = p.look_at || p.look_at_lonlat;
    if (look_at && (p.heading_deg || p.pitch_deg))
        throw Error("camera direction given both as a look-at point and as heading/pitch: give "
                    "one");
    if (p.heading_deg.has_value() != p.pitch_deg.has_value())
        throw Error("camera heading and pitch go together: give both");
    const bool has_position = p.position || p.position_lonlat;
    if (p.heading_deg && !has_position)
        throw Error("camera heading/pitch need a camera position");
    if (p.above_ground && !has_position)
        throw Error("camera height above the ground needs a camera position");
    checkParameter("exaggeration", p.exaggeration, lod::SelectionSettings::kExaggerationRange);

    if (frame && frame->onEllipsoid())
        return resolveOnGlobe(query, p, *frame);
    const TerrainGeoreference& geo = query.georeference();
    ResolvedCamera out;
    if (has_position) {
        glm::dvec3 position;
        if (p.position) {
            position = *p.position;
        } else {
            const glm::dvec3 ll = *p.position_lonlat;
            checkParameter("camera height (m)", ll.z, lod::kCameraCoordinateRange);
            const glm::dvec2 local = geo.toLocal({ll.x, ll.y}, PointSpace::LonLat);
            position = {local.x, local.y, ll.z};
        }
        checkParameters("camera position", &position.x, 3, lod::kCameraCoordinateRange);
        if (p.above_ground)
            position.z +=
                groundAt(query, {position.x, position.y}, "the camera position", p.exaggeration);
        checkParameters("camera position", &position.x, 3, lod::kCameraCoordinateRange);
        out.position = position;
        if (p.heading_deg)
            // A point one kilometre ahead: lod::Camera only needs the direction.
            out.look_at =
                position + 1000.0 * lod::headingPitchDirection(*p.heading_deg, *p.pitch_deg);
    }
    if (p.look_at) {
        checkParameters("look-at point", &p.look_at->x, 3, lod::kCameraCoordinateRange);
        out.look_at = *p.look_at;
    } else if (p.look_at_lonlat) {
        const glm::dvec3 ll = *p.look_at_lonlat;
        const glm::dvec2 local = geo.toLocal({ll.x, ll.y}, PointSpace::LonLat);
        const double z =
            std::isnan(ll.z) ? groundAt(query, local, "the look-at point", p.exaggeration) : ll.z;
        checkParameter("look-at height (m)", z, lod::kCameraCoordinateRange);
        out.look_at = glm::dvec3(local.x, local.y, z);
    }
    return out;
}

} // namespace ridge
