#include "ridge/io/geographic.h"

#include "ridge/core/error.h"
#include "ridge/core/parameter_check.h"

#include <gdal.h>
#include <proj.h>

#include <cmath>

namespace ridge::io {

// One PROJ context per transform: PJ objects are not thread-safe, and a private context keeps
// one transform's errors from another's.
struct GeographicTransform::State {
    PJ_CONTEXT* context = nullptr;
    PJ* transform = nullptr; // WGS 84 lon/lat → CRS x/y, both east-first
    ~State()
    {
        if (transform)
            proj_destroy(transform);
        if (context)
            proj_context_destroy(context);
    }
};

namespace {

std::string projError(PJ_CONTEXT* context, int code)
{
    const char* text = code ? proj_context_errno_string(context, code) : nullptr;
    return text ? text : "unknown PROJ error";
}

std::string projError(PJ_CONTEXT* context)
{
    return projError(context, proj_context_errno(context));
}

} // namespace

std::string crsReadProblem(const std::string& crs_wkt)
{
    PJ_CONTEXT* context = proj_context_create();
    if (!context)
        return "PROJ context could not be created";
    // PROJ logs its parse errors on stderr as well: the caller reports them.
    proj_log_level(context, PJ_LOG_NONE);
    PJ* crs = proj_create(context, crs_wkt.c_str());
    std::string problem;
    if (!crs)
        problem = projError(context);
    else if (!proj_is_crs(crs))
        problem = "not a coordinate reference system";
    if (crs)
        proj_destroy(crs);
    proj_context_destroy(context);
    return problem;
}

GeographicTransform::GeographicTransform(const std::string& crs_wkt, const std::string& what)
    : state_(std::make_unique<State>()), what_(what)
{
    if (crs_wkt.empty())
        throw Error(what + ": has no CRS (the source raster was not georeferenced): longitude/"
                           "latitude cannot be converted");
    State& s = *state_;
    s.context = proj_context_create();
    if (!s.context)
        throw Error(what + ": PROJ context could not be created");
    // Failures come back as errors naming the point (projError), not as lines on stderr: a
    // projected grid's lattice probes PROJ beyond its domain on purpose (lod/projected_grid.h).
    proj_log_level(s.context, PJ_LOG_NONE);
    PJ* crs = proj_create(s.context, crs_wkt.c_str());
    if (!crs)
        throw Error(what + ": PROJ cannot read the CRS (" + projError(s.context) + ")");
    const PJ_TYPE type = proj_get_type(crs);
    geographic_ = type == PJ_TYPE_GEOGRAPHIC_2D_CRS || type == PJ_TYPE_GEOGRAPHIC_3D_CRS;
    if (const char* name = proj_get_name(crs))
        name_ = name;
    PJ* wgs84 = proj_create(s.context, "EPSG:4326");
    PJ* raw =
        wgs84 ? proj_create_crs_to_crs_from_pj(s.context, wgs84, crs, nullptr, nullptr) : nullptr;
    const std::string reason = raw ? std::string() : projError(s.context);
    if (wgs84)
        proj_destroy(wgs84);
    proj_destroy(crs);
    if (!raw)
        throw Error(what + ": PROJ finds no transformation between WGS 84 and the CRS (" + reason +
                    ")");
    s.transform = proj_normalize_for_visualization(s.context, raw);
    proj_destroy(raw);
    if (!s.transform)
        throw Error(what + ": PROJ cannot order the CRS's axes east first (" +
                    projError(s.context) + ")");
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
    proj_errno_reset(state_->transform);
    const PJ_COORD out =
        proj_trans(state_->transform, PJ_FWD, proj_coord(longitude, latitude, 0.0, 0.0));
    if (!std::isfinite(out.xy.x) || !std::isfinite(out.xy.y))
        throw Error(what_ + ": longitude " + formatNumber(longitude) + ", latitude " +
                    formatNumber(latitude) + " cannot be projected to " + name_ + " (" +
                    projError(state_->context, proj_errno(state_->transform)) + ")");
    return {out.xy.x, out.xy.y};
}

std::array<double, 2> GeographicTransform::toLonLat(double x, double y) const
{
    const double xy[2] = {x, y};
    checkParameters("CRS point (x, y)", xy, 2, ValueRange::any());
    proj_errno_reset(state_->transform);
    const PJ_COORD out = proj_trans(state_->transform, PJ_INV, proj_coord(x, y, 0.0, 0.0));
    if (!std::isfinite(out.lp.lam) || !std::isfinite(out.lp.phi))
        throw Error(what_ + ": " + name_ + " point " + formatNumber(x) + ", " + formatNumber(y) +
                    " has no longitude/latitude (" +
                    projError(state_->context, proj_errno(state_->transform)) + ")");
    return {out.lp.lam, out.lp.phi};
}

std::string formatDms(double degrees, bool longitude)
{
    // GDAL's own formatter, so that `ridge info` prints corners exactly as gdalinfo does.
    return GDALDecToDMS(degrees, longitude ? "Long" : "Lat", 2);
}

} // namespace ridge::io
