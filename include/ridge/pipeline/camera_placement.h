#pragma once
// A camera given the ways a user may give one (`render`, `view`, bench path files), resolved
// into the terrain frame lod::Camera takes: a position in local metres or in longitude,
// latitude and height; a look-at point in either, or a heading and pitch (lod/
// camera_orientation.h: degrees clockwise from grid north, degrees above the horizon).
//
// Heights are metres in the archive's vertical datum (what its samples are), absolute by
// default; `above_ground` makes the position's height relative to the finest surface under it
// (HeightQuery). A look-at point given as longitude/latitude without a height looks at the
// finest surface there. Longitude/latitude go through PROJ (TerrainGeoreference), WGS 84.
#include "ridge/lod/terrain_frame.h"
#include "ridge/pipeline/height_query.h"

#include <glm/vec3.hpp>

#include <optional>

namespace ridge {

struct CameraPlacement {
    // At most one of each pair; nothing at all leaves the caller's default camera.
    std::optional<glm::dvec3> position;        // local x, y, z metres
    std::optional<glm::dvec3> position_lonlat; // longitude°, latitude°, height m
    bool above_ground = false;                 // the position's height is above the surface
    std::optional<glm::dvec3> look_at;         // local x, y, z metres
    std::optional<glm::dvec3> look_at_lonlat;  // longitude°, latitude°, height m (NaN: ground)
    std::optional<double> heading_deg;         // with pitch_deg, instead of a look-at point
    std::optional<double> pitch_deg;
    // The vertical exaggeration the camera will be drawn with (RenderSettings::exaggeration):
    // heights given are in the drawn space, and the ground a height is relative to, or a
    // look-at point without a height rests on, is the drawn ground, k times the true one.
    double exaggeration = 1.0;

    bool empty() const
    {
        return !position && !position_lonlat && !look_at && !look_at_lonlat && !heading_deg &&
               !pitch_deg;
    }
};

struct ResolvedCamera {
    std::optional<glm::dvec3> position; // terrain frame; unset: the caller's default
    std::optional<glm::dvec3> look_at;  // unset: the caller's default (e.g. the centre)
};

// Throws ridge::Error naming the parameters for conflicting or incomplete placements (both
// position forms, a look-at point and a heading, a heading without a pitch or a position,
// above_ground without a position), for coordinates off the ranges (lod::Camera's,
// longitude/latitude's, heading/pitch's), for a lon/lat position off the raster when its
// height is above the ground, and for an archive without the CRS a lon/lat form needs.
// `frame`: the frame the camera is for (the renderer's); without one, or on a plane, the
// query's own plane frame. On a globe (lod::TerrainFrame::onEllipsoid) the result is in its
// world (ECEF): longitude/latitude are WGS 84 on its ellipsoid, heights above it; local
// x, y are the plane's metric grid coordinates mapped through the frame, z a height; heading
// is clockwise from true north and pitch above the local horizon at the camera.
ResolvedCamera resolveCameraPlacement(HeightQuery& query, const CameraPlacement& placement,
                                      const lod::TerrainFrame* frame = nullptr);

} // namespace ridge
