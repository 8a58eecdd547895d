#include "ridge/lod/archive_frame.h"

#include "ridge/archive/archive_reader.h"
#include "ridge/core/error.h"
#include "ridge/core/parameter_check.h"
#include "ridge/io/geographic.h"

#include <cmath>
#include <memory>
#include <numbers>

namespace ridge::lod {

namespace {

constexpr double kDegree = std::numbers::pi / 180.0;

// A longitude span that misses 360° by at most this fraction of a column is a whole turn
// (ETOPO5's file states 0.0833341° for 5', 0.04 of a column short over 4320 columns).
constexpr double kWrapTolerance = 0.05;

// The ellipsoid grid of a geographic archive, or why there is none.
GeodeticGrid geographicGrid(const archive::ArchiveReader& reader, const std::string& what)
{
    const archive::GeoreferenceMetadata& geo = reader.metadata().georeference;
    const std::string prefix = what + ": cannot lie on the ellipsoid: ";
    if (!geo.geotransform || geo.crs_wkt.empty())
        throw Error(prefix + "it has no " + (geo.geotransform ? "CRS" : "geotransform") +
                    " (build it from a georeferenced raster)");
    const std::array<double, 6>& gt = *geo.geotransform;
    if (gt[2] != 0.0 || gt[4] != 0.0)
        throw Error(prefix + "its grid is rotated (geotransform terms 2 and 4 not 0)");
    if (!(gt[1] > 0.0) || !(gt[5] < 0.0))
        throw Error(prefix +
                    "its grid is not north-up with columns running east "
                    "(pixel size " +
                    formatNumber(gt[1]) + ", " + formatNumber(gt[5]) + ")");
    const PyramidGeometry& g = reader.geometry();
    const int w = g.width(), h = g.height();
    // Sample centres (pixel-is-area: pixel/line + ½).
    const double x0 = gt[0] + 0.5 * gt[1], y0 = gt[3] + 0.5 * gt[5];
    const double lat_north = y0, lat_south = y0 + (h - 1) * gt[5];
    const double pole_slack = 1e-6 * std::abs(gt[5]);
    if (lat_north > 90.0 + pole_slack || lat_south < -90.0 - pole_slack)
        throw Error(prefix + "its samples reach latitude " +
                    formatNumber(lat_north > 90.0 ? lat_north : lat_south) + "°, beyond the pole");
    const double span = (w - 1) * gt[1];
    if (span > 360.0 + kWrapTolerance * gt[1]) // ETOPO5's 5' are stated a little wide
        throw Error(prefix + "its samples span " + formatNumber(span) +
                    "° of longitude, more than the 360° around the Earth");

    // The datum: WGS 84 longitude and latitude of the centre sample through PROJ; the
    // difference to the CRS's own is a shift of metres, the same across the raster.
    const double xc = x0 + 0.5 * (w - 1) * gt[1], yc = y0 + 0.5 * (h - 1) * gt[5];
    std::array<double, 2> wgs84;
    try {
        wgs84 = io::GeographicTransform(geo.crs_wkt, what).toLonLat(xc, yc);
    } catch (const Error& e) {
        throw Error(prefix + e.what());
    }
    double shift_lon = wgs84[0] - xc;
    shift_lon -= 360.0 * std::round(shift_lon / 360.0);
    const double shift_lat = wgs84[1] - yc;
    if (std::abs(shift_lon) > 0.1 || std::abs(shift_lat) > 0.1)
        throw Error(prefix +
                    "its CRS's longitude and latitude are not degrees in a datum near "
                    "WGS 84 (the centre moves by " +
                    formatNumber(shift_lon) + "°, " + formatNumber(shift_lat) + "°)");

    GeodeticGrid grid;
    grid.lon0 = (x0 + shift_lon) * kDegree;
    grid.lat0 = std::min(90.0, std::max(-90.0, y0 + shift_lat)) * kDegree;
    grid.dlon = gt[1] * kDegree;
    grid.dlat = gt[5] * kDegree;
    if (const int64_t wrap = wrapColumnsOf(reader); wrap > 0) {
        grid.wrap_columns = wrap;
        grid.dlon = 2.0 * std::numbers::pi / double(wrap); // exactly a whole turn
    }
    return grid;
}

// The globe frame of a projected archive: PROJ's map from its grid to WGS 84 longitude and
// latitude, sampled into a lattice the frame and the shaders interpolate (lod/projected_grid.h).
// `reader` has a geotransform and a CRS (terrainFrameOf sends only those).
TerrainFrame projectedFrame(const archive::ArchiveReader& reader, const std::string& what)
{
    const archive::GeoreferenceMetadata& geo = reader.metadata().georeference;
    const std::string prefix = what + ": cannot lie on the ellipsoid: ";
    const std::array<double, 6> gt = geo.geotransform.value();
    std::optional<io::GeographicTransform> transform;
    try {
        transform.emplace(geo.crs_wkt, what);
    } catch (const Error& e) {
        throw Error(prefix + e.what());
    }
    // Sample centres (pixel-is-area: pixel/line + ½), through the full affine geotransform.
    auto toGeodetic = [&](double c, double r) -> std::optional<std::array<double, 2>> {
        const double x = gt[0] + (c + 0.5) * gt[1] + (r + 0.5) * gt[2];
        const double y = gt[3] + (c + 0.5) * gt[4] + (r + 0.5) * gt[5];
        try {
            const std::array<double, 2> lonlat = transform->toLonLat(x, y);
            return std::array<double, 2>{lonlat[0] * kDegree, lonlat[1] * kDegree};
        } catch (const Error&) {
            return std::nullopt;
        }
    };
    const PyramidGeometry& g = reader.geometry();
    LatticeRequest request;
    request.columns_end = request.rows_end = double(g.cells()) * double(g.step(0));
    request.last_column = g.width() - 1;
    request.last_row = g.height() - 1;
    std::shared_ptr<const ProjectedGrid> grid;
    try {
        grid = std::make_shared<const ProjectedGrid>(
            ProjectedGrid::build(Ellipsoid::wgs84(), request, toGeodetic));
    } catch (const Error& e) {
        throw Error(prefix + transform->crsName() + ": " + e.what());
    }
    const archive::Header& h = reader.header();
    return TerrainFrame::projected(g, h.spacing_x, h.spacing_y, std::move(grid));
}

} // namespace

int64_t wrapColumnsOf(const archive::ArchiveReader& reader)
{
    const archive::GeoreferenceMetadata& geo = reader.metadata().georeference;
    if (!geo.geotransform || geo.crs_wkt.empty() || !geo.geographic)
        return 0;
    const std::array<double, 6>& gt = *geo.geotransform;
    if (gt[2] != 0.0 || gt[4] != 0.0 || !(gt[1] > 0.0) || !(gt[5] < 0.0))
        return 0;
    const int64_t w = reader.geometry().width();
    const double period = 360.0 / gt[1];
    const double whole = std::round(period);
    if (std::abs(period - whole) <= kWrapTolerance &&
        (w == int64_t(whole) || w == int64_t(whole) + 1))
        return int64_t(whole);
    return 0;
}

std::string_view frameChoiceName(FrameChoice c)
{
    switch (c) {
    case FrameChoice::Plane:
        return "plane";
    case FrameChoice::Ellipsoid:
        return "ellipsoid";
    case FrameChoice::Auto:
        break;
    }
    return "auto";
}

std::optional<FrameChoice> parseFrameChoice(std::string_view name)
{
    for (FrameChoice c : {FrameChoice::Auto, FrameChoice::Plane, FrameChoice::Ellipsoid})
        if (frameChoiceName(c) == name)
            return c;
    return std::nullopt;
}

TerrainFrame terrainFrameOf(const archive::ArchiveReader& reader, FrameChoice choice,
                            const std::string& what)
{
    // The header's spacings (ground metres of a sample step at the raster's centre) keep
    // their meaning on a globe: the grid's metric coordinates that the local point space,
    // the texel criterion and extents use are the plane's.
    const archive::Header& h = reader.header();
    TerrainFrame plane(reader.geometry(), h.spacing_x, h.spacing_y);
    if (choice == FrameChoice::Plane)
        return plane;
    GeodeticGrid grid;
    if (choice == FrameChoice::Auto) {
        // The globe when the raster goes round it, decided before PROJ's database is opened
        // (tens of MB); anything else keeps the plane it was always drawn on.
        if (wrapColumnsOf(reader) == 0)
            return plane;
        try {
            grid = geographicGrid(reader, what);
        } catch (const Error&) {
            return plane;
        }
    } else if (const archive::GeoreferenceMetadata& geo = reader.metadata().georeference;
               geo.geotransform && !geo.crs_wkt.empty() && !geo.geographic) {
        return projectedFrame(reader, what);
    } else {
        grid = geographicGrid(reader, what);
    }
    return TerrainFrame::ellipsoid(reader.geometry(), h.spacing_x, h.spacing_y, grid);
}

} // namespace ridge::lod
