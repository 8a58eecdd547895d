#include "ridge/io/geographic.h"

#include "proj_support.h"

#include "ridge/core/error.h"
#include "ridge/core/parameter_check.h"

#include <gdal.h>
#include <proj.h>

#include <cmath>

namespace ridge::io {

// One PROJ context per transform: PJ objects are not thread-safe, and a private context keeps
// one transform's errors from another's.
struct GeographicTransform::State {
    detail::ProjContext context;
    detail::ProjObject transform; // WGS 84 lon/lat → CRS x/y, both east-first; before context
};

using detail::projError;

std::string crsReadProblem(const std::string& crs_wkt)
{
    detail::ProjContext context;
    try {
        context = detail::newProjContext(); // silent: the caller reports the problem
    } catch (const Error& e) {
        return e.what();
    }
    const detail::ProjObject crs(proj_create(context.get(), crs_wkt.c_str()));
    if (!crs)
        return projError(context.get());
    if (!proj_is_crs(crs.get()))
        return "not a coordinate reference system";
    return {};
}

GeographicTransform::GeographicTransform(const std::string& crs_wkt, const std::string& what)
    : state_(std::make_unique<State>()), what_(what)
{
    if (crs_wkt.empty())
        throw Error(what + ": has no CRS (the source raster was not georeferenced): longitude/"
                           "latitude cannot be converted");
    State& s = *state_;
    // Failures come back as errors naming the point (projError), not as lines on stderr: a
    // projected grid's lattice probes PROJ beyond its domain on purpose (lod/projected_grid.h).
    s.context = detail::newProjContext(what);
    PJ_CONTEXT* ctx = s.context.get();
    const detail::ProjObject crs(proj_create(ctx, crs_wkt.c_str()));
    if (!crs)
        throw Error(what + ": PROJ cannot read the CRS (" + projError(ctx) + ")");
    const PJ_TYPE type = proj_get_type(crs.get());
    geographic_ = type == PJ_TYPE_GEOGRAPHIC_2D_CRS || type == PJ_TYPE_GEOGRAPHIC_3D_CRS;
    name_ = detail::projName(crs.get());
    const detail::ProjObject wgs84(proj_create(ctx, "EPSG:4326"));
    const detail::ProjObject raw(
        wgs84 ? proj_create_crs_to_crs_from_pj(ctx, wgs84.get(), crs.get(), nullptr, nullptr)
              : nullptr);
    if (!raw)
        throw Error(what + ": PROJ finds no transformation between WGS 84 and the CRS (" +
                    projError(ctx) + ")");
    s.transform.reset(proj_normalize_for_visualization(ctx, raw.get()));
    if (!s.transform)
        throw Error(what + ": PROJ cannot order the CRS's axes east first (" + projError(ctx) +
                    ")");
}

GeographicTransform::~GeographicTransform() = default;
GeographicTransform::GeographicTransform(GeographicTransform&&) noexcept = default;
GeographicTransform& GeographicTransform::operator=(GeographicTransform&&) noexcept = default;

std::array<double, 2> GeographicTransform::fromLonLat(double longitude, double latitude) const
{
    checkParameter("longitude (degrees)", longitude,
                   ValueRange::closed(-kMaxAbsLongitudeDegrees, kMaxAbsLongitudeDegrees));
    checkParameter("latitude (degrees)", latitude,
                   ValueRange::closed(-kMaxAbsLatitudeDegrees, kMaxAbsLatitudeDegrees));
    proj_errno_reset(state_->transform.get());
    const PJ_COORD out =
        proj_trans(state_->transform.get(), PJ_FWD, proj_coord(longitude, latitude, 0.0, 0.0));
    if (!std::isfinite(out.xy.x) || !std::isfinite(out.xy.y))
        throw Error(what_ + ": longitude " + formatNumber(longitude) + ", latitude " +
                    formatNumber(latitude) + " cannot be projected to " + name_ + " (" +
                    projError(state_->context.get(), proj_errno(state_->transform.get())) + ")");
    return {out.xy.x, out.xy.y};
}

std::array<double, 2> GeographicTransform::toLonLat(double x, double y) const
{
    const double xy[2] = {x, y};
    checkParameters("CRS point (x, y)", xy, 2, ValueRange::any());
    proj_errno_reset(state_->transform.get());
    const PJ_COORD out = proj_trans(state_->transform.get(), PJ_INV, proj_coord(x, y, 0.0, 0.0));
    if (!std::isfinite(out.lp.lam) || !std::isfinite(out.lp.phi))
        throw Error(what_ + ": " + name_ + " point " + formatNumber(x) + ", " + formatNumber(y) +
                    " has no longitude/latitude (" +
                    projError(state_->context.get(), proj_errno(state_->transform.get())) + ")");
    return {out.lp.lam, out.lp.phi};
}

std::string formatDms(double degrees, bool longitude)
{
    // GDAL's own formatter, so that `ridge info` prints corners exactly as gdalinfo does.
    return GDALDecToDMS(degrees, longitude ? "Long" : "Lat", 2);
}

} // namespace ridge::io
