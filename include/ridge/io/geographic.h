#pragma once
// Longitude/latitude (WGS 84, degrees, longitude first) to and from an archive's CRS, through
// PROJ. The only place ridge talks to PROJ; PROJ headers never appear in public headers.
//
// The transformation is PROJ's proj_create_crs_to_crs("EPSG:4326", CRS) made east-first on
// both sides with proj_normalize_for_visualization, so that it works in the order GDAL's
// geotransforms use (x = easting or longitude, y = northing or latitude) whatever axis order
// the CRS's definition states. Geographic archives go the same way (a no-op for WGS 84, a
// datum shift for others).
#include <array>
#include <memory>
#include <string>

namespace ridge::io {

// Longitude accepted in [-360, 360] (rasters in 0..360 conventions exist), latitude in
// [-90, 90], degrees; both finite.
inline constexpr double kMaxAbsLongitudeDegrees = 360.0;
inline constexpr double kMaxAbsLatitudeDegrees = 90.0;

// Empty when PROJ reads `crs_wkt` as a CRS (what `extract` must write with the raster), else
// PROJ's reason ("missing , or ]"). Does not look for a transformation to WGS 84.
std::string crsReadProblem(const std::string& crs_wkt);

class GeographicTransform {
  public:
    // `crs_wkt` as stored in an archive (georeference.crs_wkt). Throws ridge::Error when it is
    // empty ("... has no CRS ...") or PROJ cannot read it or find a transformation; `what`
    // (e.g. the archive path) starts the message.
    GeographicTransform(const std::string& crs_wkt, const std::string& what);
    ~GeographicTransform();
    GeographicTransform(GeographicTransform&&) noexcept;
    GeographicTransform& operator=(GeographicTransform&&) noexcept;

    // CRS x, y (easting/northing, or longitude/latitude in the CRS's own datum) of a WGS 84
    // point. Throws ridge::Error for a non-finite or out-of-range longitude or latitude, or
    // when PROJ cannot transform the point.
    std::array<double, 2> fromLonLat(double longitude, double latitude) const;
    // WGS 84 longitude, latitude of CRS x, y. Throws ridge::Error for non-finite input or a
    // point PROJ cannot transform (outside the projection's domain).
    std::array<double, 2> toLonLat(double x, double y) const;

    // Whether the CRS itself is geographic (x, y are degrees).
    bool geographic() const { return geographic_; }
    // The CRS's name as PROJ reports it ("WGS 84 / UTM zone 45N").
    const std::string& crsName() const { return name_; }

  private:
    struct State;
    std::unique_ptr<State> state_;
    bool geographic_ = false;
    std::string name_;
    std::string what_;
};

// gdalinfo's degrees-minutes-seconds: "86d55'30.00\"E", "27d59'16.80\"N" (seconds to two
// decimals, hemisphere letter last). `longitude` picks E/W or N/S.
std::string formatDms(double degrees, bool longitude);

} // namespace ridge::io
