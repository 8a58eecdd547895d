#pragma once
// The geoid of a vertical datum as PROJ knows it: N, metres of the geoid above the WGS 84
// ellipsoid, at longitude/latitude points, so that heights above the geoid (H) become
// heights above the ellipsoid, h = H + N — what `ridge serve` does for Cesium, which places
// quantized-mesh heights on the ellipsoid, when an archive's heights are above EGM96 or
// another registered vertical datum. The same transformation `ridge build --vshift` applies
// (src/io/geoid_shift.h): PROJ's best operation whose grid is installed, never its
// "ballpark" one (N = 0).
#include <array>
#include <memory>
#include <span>
#include <string>

namespace ridge::io {

class GeoidModel {
  public:
    // The geoid of EPSG vertical CRS `vertical_epsg` ("EGM96 height" is 5773). Throws
    // ridge::Error naming `what` and the datum when PROJ has no usable transformation (a
    // grid not installed, a code that is not a vertical CRS).
    GeoidModel(const std::string& what, int vertical_epsg, const std::string& datum_name);
    ~GeoidModel();
    GeoidModel(const GeoidModel&) = delete;
    GeoidModel& operator=(const GeoidModel&) = delete;

    // out[i] = N at (longitude, latitude) lonlat[i], degrees. Throws ridge::Error naming the
    // point where the geoid grid does not reach. Not thread-safe (PROJ objects are not).
    void undulations(std::span<const std::array<double, 2>> lonlat, std::span<double> out) const;
    // PROJ's name of the transformation ("Inverse of WGS 84 to EGM96 height (1)").
    const std::string& operation() const;

  private:
    struct State;
    std::unique_ptr<State> state_;
};

} // namespace ridge::io
