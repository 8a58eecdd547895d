#pragma once
// Heights above a geoid become heights above the ellipsoid: h = H + N(λ, φ).
//
// SRTM-like DEMs give heights above EGM96 (a gravity-related vertical CRS); the globe draws
// heights above the WGS 84 ellipsoid, 100 m away in places (N runs from −106 m south of India
// to +85 m over New Guinea). PROJ knows the transformation and its grid (proj-data ships
// egm96_15.gtx); this file only asks PROJ for it, refuses one whose grid is missing instead
// of PROJ's silent "ballpark" fallback (N = 0), and evaluates N at the samples' centres.
#include "ridge/core/error.h"
#include "ridge/io/crs_summary.h"
#include "ridge/io/raster_source.h"

#include <array>
#include <memory>
#include <string>

namespace ridge::io::detail {

// Whether heights above vertical datum `datum` are shifted to the ellipsoid under `mode`: Ellipsoid
// always (a source without a known, registered datum is an error then), None never, Auto when the
// datum is a registered vertical CRS.
bool wantsGeoidShift(VerticalShift mode, const VerticalDatum& datum);

class GeoidShift {
  public:
    // What undulationsAt throws for a point the transformation's grid does not cover
    // (callers name the point their own way; an Error for those who do not catch it).
    struct OutsideGrid : Error {
        OutsideGrid(size_t i, std::string w)
            : Error("point " + std::to_string(i) + " at " + w + " is outside the geoid grid"),
              index(i), where(std::move(w))
        {
        }
        size_t index;
        std::string where;
    };

    // The transformation from (x, y, H above `from`) in the horizontal CRS `horizontal_wkt`
    // (a compound CRS's horizontal part is taken) to (x, y, h above its ellipsoid), for a
    // grid with GDAL geotransform `gt`. Throws Error("path: ...") naming the datum and, when
    // PROJ lacks them, the grids it would need.
    GeoidShift(const std::string& path, const std::string& horizontal_wkt,
               const VerticalDatum& from, const std::array<double, 6>& gt);
    ~GeoidShift();
    GeoidShift(const GeoidShift&) = delete;
    GeoidShift& operator=(const GeoidShift&) = delete;

    // N in metres at the centres of samples [0, width) of rows [y0, y0 + rows): out[rows *
    // width]. Throws Error naming the sample where the grid does not cover it. Not
    // thread-safe (PROJ objects are not).
    void undulations(int y0, int rows, int width, double* out) const;
    // N in metres at `count` points (x[i], y[i]) of the horizontal CRS (longitude, latitude
    // for a geographic one): out[i]. Throws Error naming the point where the grid does not
    // cover it. Not thread-safe. x and y are taken as scratch (longitudes wrapped).
    void undulationsAt(double* x, double* y, size_t count, double* out) const;

    const VerticalDatum& from() const { return from_; }
    // PROJ's name of the transformation ("Inverse of WGS 84 to EGM96 height (1)").
    const std::string& operation() const { return operation_; }
    // What the heights are above afterwards: "WGS 84 ellipsoidal height".
    const std::string& target() const { return target_; }

  private:
    struct State;
    std::unique_ptr<State> state_;
    std::string path_;
    VerticalDatum from_;
    std::string operation_;
    std::string target_;
    std::array<double, 6> gt_;
    bool geographic_ = false;
};

} // namespace ridge::io::detail
