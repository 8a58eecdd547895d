#pragma once
// Where an archive's samples lie, in the four coordinate systems a point may be given in, and
// the conversions between them (GL-free; PROJ behind io::GeographicTransform).
//
//   Local  the terrain frame (lod/terrain_frame.h), metres: x = column·spacing_x east of the
//          first column, y = (height − 1 − row)·spacing_y north of the last row.
//   Pixel  GDAL pixel/line, pixel-is-area: finest sample (column, row) is the centre of GDAL
//          pixel (column, row), i.e. pixel/line (column + 0.5, row + 0.5); the raster covers
//          pixel/line [0, width] x [0, height]. This is how ridge builds: sample (c, r) is the
//          source's pixel (c, r), and extract writes level geotransforms that keep pixel
//          centres on their samples (docs/FORMAT.md).
//   Crs    the archive CRS: x = gt0 + P·gt1 + L·gt2, y = gt3 + P·gt4 + L·gt5 with the stored
//          geotransform (GDAL order; x easting or longitude, y northing or latitude).
//   LonLat WGS 84 longitude, latitude in degrees, through PROJ.
//
// Local and Pixel always work; Crs needs a stored geotransform, LonLat a CRS as well. Both
// throw ridge::Error naming the archive and what it lacks otherwise.
#include "ridge/archive/archive_reader.h"
#include "ridge/io/geographic.h"
#include "ridge/lod/terrain_frame.h"

#include <glm/vec2.hpp>

#include <array>
#include <optional>
#include <string>
#include <string_view>

namespace ridge {

enum class PointSpace { Local, Pixel, Crs, LonLat };
// "local", "pixel", "crs", "lonlat".
std::string_view pointSpaceName(PointSpace space);

class TerrainGeoreference {
  public:
    // Reads the header's spacings and the stored geotransform and CRS. Throws ridge::Error
    // when the geotransform cannot be inverted (a degenerate, zero-area pixel).
    explicit TerrainGeoreference(const archive::ArchiveReader& reader);

    const lod::TerrainFrame& frame() const { return frame_; }
    bool hasGeotransform() const { return geotransform_.has_value(); }
    bool hasCrs() const { return !crs_wkt_.empty(); }
    // True when the CRS itself is geographic (lon/lat degrees); false without a CRS.
    bool geographicCrs() const { return geographic_; }

    // `point` in `from` → local metres, and back. Throws ridge::Error for non-finite
    // coordinates, a longitude/latitude out of range, or a space the archive lacks.
    glm::dvec2 toLocal(glm::dvec2 point, PointSpace from) const;
    glm::dvec2 fromLocal(glm::dvec2 local, PointSpace to) const;
    // The same through pixel/line, the geotransform's own space: a pixel/line given is used
    // as is (sample centres stay exact), a CRS point goes through the inverse geotransform.
    // On a geographic grid that goes round the Earth (a 0..360° ETOPO-like raster, its column
    // 0 repeated at 360°) a longitude or CRS x in any period lands in the grid's own.
    glm::dvec2 toPixel(glm::dvec2 point, PointSpace from) const;
    glm::dvec2 localOfPixel(glm::dvec2 pixel) const;

    // Meridian convergence at local point `local`: the angle in degrees, clockwise, from grid
    // north (the local frame's +y) to true north. 0 for a north-up geographic archive; up to
    // a few degrees in a transverse Mercator zone. Needs a CRS.
    double convergenceDegrees(glm::dvec2 local) const;

  private:
    const io::GeographicTransform& geographic() const;
    std::array<double, 2> pixelToCrs(double pixel, double line) const;
    std::array<double, 2> crsToPixel(double x, double y) const;
    // A pixel x of a grid that goes round the Earth taken into its first period.
    glm::dvec2 wrapped(glm::dvec2 pixel) const;

    std::string path_;
    lod::TerrainFrame frame_;
    std::optional<std::array<double, 6>> geotransform_;
    std::array<double, 6> inverse_{};
    std::string crs_wkt_;
    bool geographic_ = false;
    std::optional<io::GeographicTransform> transform_; // when a CRS and geotransform exist
    std::string transform_error_;                      // why transform_ is missing
    double wrap_columns_ = 0.0; // columns in 360° when the grid goes round the Earth, else 0
};

} // namespace ridge
