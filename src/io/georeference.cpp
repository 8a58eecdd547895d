#include "georeference.h"

#include "ridge/core/error.h"
#include "ridge/io/crs_summary.h"

#include <cpl_conv.h>
#include <ogr_srs_api.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace ridge::io::detail {

namespace {

// GDAL reports this when a raster has no geotransform at all.
constexpr std::array<double, 6> kGdalDefaultGeotransform{0, 1, 0, 0, 0, 1};

std::string exportWkt(OGRSpatialReferenceH srs)
{
    const char* const wkt2[] = {"FORMAT=WKT2_2019", nullptr};
    char* wkt = nullptr;
    if (OSRExportToWktEx(srs, &wkt, wkt2) != OGRERR_NONE || !wkt) {
        CPLFree(wkt);
        wkt = nullptr;
        if (OSRExportToWkt(srs, &wkt) != OGRERR_NONE || !wkt) {
            CPLFree(wkt);
            return {};
        }
    }
    std::string out = wkt;
    CPLFree(wkt);
    return out;
}

struct Spacing {
    double x = 0;
    double y = 0;
};

// Ground lengths of one column step (gt[1], gt[4]) and one row step (gt[2], gt[5]) of a
// lon/lat grid, on the CRS's ellipsoid at the raster's centre latitude. The local metric
// ds² = (N cosφ dλ)² + (M dφ)² also measures rotated grids correctly.
Spacing geographicSpacing(OGRSpatialReferenceH srs, const std::array<double, 6>& gt, int width,
                          int height)
{
    const double a = OSRGetSemiMajor(srs, nullptr);
    const double b = OSRGetSemiMinor(srs, nullptr);
    const double e2 = a > 0 ? 1.0 - (b * b) / (a * a) : 0.0;
    const double radians_per_unit = OSRGetAngularUnits(srs, nullptr);

    const double centre_lat = gt[3] + gt[4] * (width / 2.0) + gt[5] * (height / 2.0);
    const double phi =
        std::clamp(centre_lat * radians_per_unit, -std::numbers::pi / 2, std::numbers::pi / 2);
    const double s = std::sin(phi);
    const double w = 1.0 - e2 * s * s;
    const double meridian_radius = a * (1.0 - e2) / (w * std::sqrt(w)); // M
    const double prime_vertical = a / std::sqrt(w);                     // N
    const double parallel_radius = prime_vertical * std::cos(phi);      // N cos(phi)

    auto length = [&](double d_lon, double d_lat) {
        return std::hypot(parallel_radius * d_lon * radians_per_unit,
                          meridian_radius * d_lat * radians_per_unit);
    };
    return {length(gt[1], gt[4]), length(gt[2], gt[5])};
}

Spacing projectedSpacing(OGRSpatialReferenceH srs, const std::array<double, 6>& gt)
{
    const double metres_per_unit = OSRGetLinearUnits(srs, nullptr);
    return {std::hypot(gt[1], gt[4]) * metres_per_unit, std::hypot(gt[2], gt[5]) * metres_per_unit};
}

bool usable(const Spacing& s)
{
    return std::isfinite(s.x) && std::isfinite(s.y) && s.x > 0 && s.y > 0;
}

} // namespace

GeoReference readGeoReference(GDALDatasetH dataset, int width, int height,
                              const IngestOptions& options)
{
    GeoReference geo;
    std::array<double, 6> gt{};
    if (GDALGetGeoTransform(dataset, gt.data()) == CE_None && gt != kGdalDefaultGeotransform) {
        geo.has_geotransform = true;
        geo.geotransform = gt;
    }

    std::optional<Spacing> spacing;
    if (OGRSpatialReferenceH srs = GDALGetSpatialRef(dataset)) {
        geo.crs_wkt = exportWkt(srs);
        geo.geographic = OSRIsGeographic(srs) != 0;
        // Without a CRS the geotransform's units are unknown, so only a CRS makes the
        // spacing trustworthy.
        if (geo.has_geotransform) {
            const Spacing s = geo.geographic ? geographicSpacing(srs, gt, width, height)
                                             : projectedSpacing(srs, gt);
            if (usable(s))
                spacing = s;
        }
    }

    // The heights' datum: the user's word first (it corrects sources that state none, or a
    // wrong one), else the vertical part of a compound CRS. A CRS PROJ cannot summarise
    // states no datum ridge can use.
    if (options.vertical_datum) {
        geo.vertical_datum = resolveVerticalDatum(*options.vertical_datum);
    } else if (!geo.crs_wkt.empty()) {
        try {
            geo.vertical_datum = summarizeCrs(geo.crs_wkt, "source CRS").vertical;
        } catch (const Error&) {
        }
    }

    if (spacing && !options.force_spacing) {
        geo.spacing_x = spacing->x;
        geo.spacing_y = spacing->y;
        geo.spacing_from_user = false;
    } else {
        geo.spacing_x = geo.spacing_y = options.spacing.value_or(1.0);
        geo.spacing_from_user = true;
    }
    return geo;
}

} // namespace ridge::io::detail
