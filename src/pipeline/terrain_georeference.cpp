#include "ridge/pipeline/terrain_georeference.h"

#include "ridge/lod/archive_frame.h"

#include "ridge/core/error.h"
#include "ridge/core/parameter_check.h"

#include <cmath>
#include <numbers>

namespace ridge {

std::string_view pointSpaceName(PointSpace space)
{
    switch (space) {
    case PointSpace::Local:
        return "local";
    case PointSpace::Pixel:
        return "pixel";
    case PointSpace::Crs:
        return "crs";
    case PointSpace::LonLat:
        return "lonlat";
    }
    return "?";
}

TerrainGeoreference::TerrainGeoreference(const archive::ArchiveReader& reader)
    : path_(reader.path()),
      frame_(reader.geometry(), reader.header().spacing_x, reader.header().spacing_y),
      geotransform_(reader.metadata().georeference.geotransform),
      crs_wkt_(reader.metadata().georeference.crs_wkt)
{
    if (geotransform_) {
        // GDALInvGeoTransform's algebra, with the degenerate case refused by name.
        const std::array<double, 6>& g = *geotransform_;
        const double det = g[1] * g[5] - g[2] * g[4];
        if (!(std::abs(det) > 0.0) || !std::isfinite(1.0 / det))
            throw Error(path_ + ": georeference.geotransform has a zero-area pixel (determinant " +
                        formatNumber(det) + "): cannot map coordinates to pixels");
        const double inv = 1.0 / det;
        inverse_ = {(g[2] * g[3] - g[0] * g[5]) * inv,  g[5] * inv,  -g[2] * inv,
                    (-g[1] * g[3] + g[0] * g[4]) * inv, -g[4] * inv, g[1] * inv};
        // GDAL inverts a north-up geotransform without the determinant (GDALInvGeoTransform's
        // special case), which rounds differently: 1/gt1 is 1200 where gt5/det is
        // 1199.9999999999998 for a 3" grid. The same algebra puts a point on a pixel edge in
        // the pixel gdallocationinfo reports (query --resampling nearest).
        if (g[2] == 0.0 && g[4] == 0.0)
            inverse_ = {-g[0] / g[1], 1.0 / g[1], 0.0, -g[3] / g[5], 0.0, 1.0 / g[5]};
    }
    if (!crs_wkt_.empty() && geotransform_) {
        try {
            transform_.emplace(crs_wkt_, path_);
            geographic_ = transform_->geographic();
        } catch (const Error& e) {
            transform_error_ = e.what(); // Local, Pixel and Crs still work
        }
    }
    // A raster that goes round the Earth: the globe's rule for its period, so that a query at
    // −155° finds what is drawn at 205° on a 0..360° grid.
    if (geographic_)
        wrap_columns_ = double(lod::wrapColumnsOf(reader));
}

glm::dvec2 TerrainGeoreference::wrapped(glm::dvec2 pixel) const
{
    if (wrap_columns_ > 0.0) // into [0.5, period + 0.5): sample centres 0 .. period
        pixel.x =
            0.5 + (pixel.x - 0.5) - wrap_columns_ * std::floor((pixel.x - 0.5) / wrap_columns_);
    return pixel;
}

const io::GeographicTransform& TerrainGeoreference::geographic() const
{
    if (transform_)
        return *transform_;
    if (!transform_error_.empty())
        throw Error(transform_error_);
    if (crs_wkt_.empty())
        throw Error(path_ + ": the archive has no CRS (the source was not georeferenced): "
                            "longitude/latitude cannot be converted");
    throw Error(path_ + ": the archive has no geotransform: longitude/latitude cannot be "
                        "converted");
}

std::array<double, 2> TerrainGeoreference::pixelToCrs(double pixel, double line) const
{
    if (!geotransform_)
        throw Error(path_ + ": the archive has no geotransform: CRS coordinates cannot be "
                            "converted (use local or pixel coordinates)");
    const std::array<double, 6>& g = *geotransform_;
    return {g[0] + pixel * g[1] + line * g[2], g[3] + pixel * g[4] + line * g[5]};
}

std::array<double, 2> TerrainGeoreference::crsToPixel(double x, double y) const
{
    if (!geotransform_)
        throw Error(path_ + ": the archive has no geotransform: CRS coordinates cannot be "
                            "converted (use local or pixel coordinates)");
    const std::array<double, 6>& v = inverse_;
    return {v[0] + x * v[1] + y * v[2], v[3] + x * v[4] + y * v[5]};
}

glm::dvec2 TerrainGeoreference::toPixel(glm::dvec2 point, PointSpace from) const
{
    // The message is built only for a bad point: batches of queries convert millions.
    if (!std::isfinite(point.x) || !std::isfinite(point.y))
        checkParameters(std::string(pointSpaceName(from)) + " point", &point.x, 2,
                        ValueRange::any());
    switch (from) {
    case PointSpace::Local:
        break;
    case PointSpace::Pixel:
        return point;
    case PointSpace::Crs: {
        const auto p = crsToPixel(point.x, point.y);
        return wrapped({p[0], p[1]});
    }
    case PointSpace::LonLat: {
        const auto crs = geographic().fromLonLat(point.x, point.y);
        const auto p = crsToPixel(crs[0], crs[1]);
        return wrapped({p[0], p[1]});
    }
    }
    return {point.x / frame_.spacingX() + 0.5,
            frame_.geometry().height() - 0.5 - point.y / frame_.spacingY()};
}

glm::dvec2 TerrainGeoreference::localOfPixel(glm::dvec2 pixel) const
{
    // Pixel centre (c + 0.5, r + 0.5) is sample (c, r).
    return {frame_.xOf(pixel.x - 0.5),
            (frame_.geometry().height() - 0.5 - pixel.y) * frame_.spacingY()};
}

glm::dvec2 TerrainGeoreference::toLocal(glm::dvec2 point, PointSpace from) const
{
    if (from == PointSpace::Local) {
        checkParameters("local point", &point.x, 2, ValueRange::any());
        return point;
    }
    return localOfPixel(toPixel(point, from));
}

glm::dvec2 TerrainGeoreference::fromLocal(glm::dvec2 local, PointSpace to) const
{
    checkParameters("local point", &local.x, 2, ValueRange::any());
    const double height = frame_.geometry().height();
    const glm::dvec2 pixel{local.x / frame_.spacingX() + 0.5,
                           height - 0.5 - local.y / frame_.spacingY()};
    switch (to) {
    case PointSpace::Local:
        return local;
    case PointSpace::Pixel:
        return pixel;
    case PointSpace::Crs: {
        const auto crs = pixelToCrs(pixel.x, pixel.y);
        return {crs[0], crs[1]};
    }
    case PointSpace::LonLat: {
        const io::GeographicTransform& t = geographic();
        const auto crs = pixelToCrs(pixel.x, pixel.y);
        const auto ll = t.toLonLat(crs[0], crs[1]);
        return {ll[0], ll[1]};
    }
    }
    return local;
}

double TerrainGeoreference::convergenceDegrees(glm::dvec2 local) const
{
    const glm::dvec2 ll = fromLocal(local, PointSpace::LonLat);
    // A step of 1e-4° (11 m) along the meridian, southwards near the north pole.
    const double step = ll.y > 89.0 ? -1e-4 : 1e-4;
    const glm::dvec2 other = toLocal({ll.x, ll.y + step}, PointSpace::LonLat);
    const glm::dvec2 north = (other - local) * (step > 0 ? 1.0 : -1.0);
    return std::atan2(north.x, north.y) * 180.0 / std::numbers::pi;
}

} // namespace ridge
