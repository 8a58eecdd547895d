// The public API's Terrain (<ridge/ridge.h>): an open archive, its description, and GL-free
// height queries and coordinate conversions over pipeline's HeightQuery and
// TerrainGeoreference.
#include "ridge/ridge.h"

#include "ridge/core/error.h"
#include "ridge/core/parameter_check.h"
#include "ridge/lod/camera.h"
#include "ridge/pipeline/camera_placement.h"
#include "ridge/pipeline/height_query.h"

#include <cmath>

namespace ridge {

namespace {

TerrainInfo describe(const archive::ArchiveReader& reader)
{
    const archive::Header& h = reader.header();
    const archive::ArchiveMetadata& m = reader.metadata();
    TerrainInfo info;
    info.path = reader.path();
    info.width = h.width;
    info.height = h.height;
    info.spacing_x = h.spacing_x;
    info.spacing_y = h.spacing_y;
    info.levels = int(h.level_count);
    info.patch_size = int(h.patch_size);
    info.patches = int64_t(reader.index().size());
    info.codec = m.build.codec;
    // The root's bounds cover every descendant (docs/FORMAT.md, index entry).
    info.min_height = reader.index().front().min_height;
    info.max_height = reader.index().front().max_height;
    info.max_error = reader.levelErrorBound(int(h.level_count) - 1);
    info.crs_wkt = m.georeference.crs_wkt;
    info.geographic = m.georeference.geographic;
    info.geotransform = m.georeference.geotransform;
    return info;
}

PointSpace spaceOf(Coordinates c)
{
    switch (c) {
    case Coordinates::Local:
        return PointSpace::Local;
    case Coordinates::Pixel:
        return PointSpace::Pixel;
    case Coordinates::Crs:
        return PointSpace::Crs;
    case Coordinates::LonLat:
        return PointSpace::LonLat;
    }
    throw Error("QueryParameters::coordinates is " + std::to_string(int(c)) +
                ": not a Coordinates value");
}

QueryResampling resamplingOf(Resampling r)
{
    switch (r) {
    case Resampling::Bilinear:
        return QueryResampling::Bilinear;
    case Resampling::Nearest:
        return QueryResampling::Nearest;
    }
    throw Error("QueryParameters::resampling is " + std::to_string(int(r)) +
                ": not a Resampling value");
}

// −1 (the finest) or a level of the archive.
void checkLevel(int finest, int level)
{
    if (level != -1)
        checkParameter("QueryParameters::level (-1: the finest)", int64_t{level}, 0, finest);
}

PointHeight pointHeightOf(const HeightSample& s)
{
    PointHeight h;
    h.level = s.level;
    h.status = s.invalid_point ? HeightStatus::InvalidPoint
               : !s.on_raster  ? HeightStatus::OffTerrain
               : s.nodata      ? HeightStatus::NoData
                               : HeightStatus::Ok;
    if (h.status == HeightStatus::Ok) {
        h.height = s.height;
        h.error_bound = s.error_bound;
        h.water = s.water;
        h.filled = s.filled;
    }
    return h;
}

// The batch through `query`: points converted to the pipeline's type, each answer to the
// API's as it comes (no per-point HeightSample array).
void queryHeights(HeightQuery& query, std::span<const std::array<double, 2>> points,
                  std::span<PointHeight> out, const QueryParameters& p)
{
    if (out.size() != points.size())
        throw Error("Terrain::heights: out has " + std::to_string(out.size()) + " entries for " +
                    std::to_string(points.size()) + " points");
    checkLevel(query.finestLevel(), p.level);
    const PointSpace space = spaceOf(p.coordinates);
    const QueryResampling resampling = resamplingOf(p.resampling);
    std::vector<glm::dvec2> converted(points.size());
    for (size_t k = 0; k < points.size(); ++k)
        converted[k] = {points[k][0], points[k][1]};
    query.sampleEach(converted, space, p.level, resampling,
                     [&](size_t k, const HeightSample& s) { out[k] = pointHeightOf(s); });
}

} // namespace

struct Terrain::Impl {
    // HeightQuery caches decoded patches, hence mutable: Terrain's queries are logically
    // const, and the API is thread-compatible (one thread at a time per Terrain).
    mutable HeightQuery query;
    TerrainInfo info;
    size_t cache_patches;

    Impl(const std::string& path, size_t cache)
        : query(path, cache), info(describe(query.reader())), cache_patches(cache)
    {
    }

    std::optional<double> heightAt(double x, double y, int level) const
    {
        const HeightSample s = query.sample({x, y}, PointSpace::Local, level);
        return s.on_raster && !s.nodata ? std::optional<double>(s.height) : std::nullopt;
    }
};

Terrain::Terrain(const std::string& archive_path, size_t cache_patches)
    : impl_(std::make_unique<Impl>(archive_path, cache_patches))
{
}
Terrain::~Terrain() = default;
Terrain::Terrain(Terrain&&) noexcept = default;
Terrain& Terrain::operator=(Terrain&&) noexcept = default;

const TerrainInfo& Terrain::info() const
{
    return impl_->info;
}

std::optional<double> Terrain::height(double x, double y) const
{
    return impl_->heightAt(x, y, -1);
}

std::optional<double> Terrain::heightAtLevel(double x, double y, int level) const
{
    if (level < 0)
        throw Error("level is " + std::to_string(level) + ": must be in [0, " +
                    std::to_string(impl_->info.levels - 1) + "]");
    return impl_->heightAt(x, y, level);
}

static LocalPoint toLocal(const HeightQuery& q, double a, double b, PointSpace from)
{
    const glm::dvec2 p = q.georeference().toLocal({a, b}, from);
    return {p.x, p.y};
}

LocalPoint Terrain::localFromPixel(double pixel, double line) const
{
    return toLocal(impl_->query, pixel, line, PointSpace::Pixel);
}

LocalPoint Terrain::localFromCrs(double x, double y) const
{
    return toLocal(impl_->query, x, y, PointSpace::Crs);
}

LocalPoint Terrain::localFromLonLat(double longitude, double latitude) const
{
    return toLocal(impl_->query, longitude, latitude, PointSpace::LonLat);
}

std::array<double, 2> Terrain::lonLatFromLocal(double x, double y) const
{
    const glm::dvec2 p = impl_->query.georeference().fromLocal({x, y}, PointSpace::LonLat);
    return {p.x, p.y};
}

double Terrain::convergenceDegrees(double x, double y) const
{
    return impl_->query.georeference().convergenceDegrees({x, y});
}

void Terrain::heights(std::span<const std::array<double, 2>> points, std::span<PointHeight> out,
                      const QueryParameters& parameters) const
{
    queryHeights(impl_->query, points, out, parameters);
}

std::vector<PointHeight> Terrain::heights(std::span<const std::array<double, 2>> points,
                                          const QueryParameters& parameters) const
{
    std::vector<PointHeight> out(points.size());
    heights(points, out, parameters);
    return out;
}

std::future<std::vector<PointHeight>>
Terrain::heightsAsync(std::vector<std::array<double, 2>> points,
                      const QueryParameters& parameters) const
{
    // What can be refused now is refused now, on the caller's thread.
    spaceOf(parameters.coordinates);
    resamplingOf(parameters.resampling);
    checkLevel(impl_->info.levels - 1, parameters.level);
    return std::async(std::launch::async, [path = impl_->info.path, cache = impl_->cache_patches,
                                           points = std::move(points), parameters] {
        HeightQuery query(path, cache);
        std::vector<PointHeight> out(points.size());
        queryHeights(query, points, out, parameters);
        return out;
    });
}

CameraPose Terrain::cameraPose(const CameraParameters& camera) const
{
    auto vec = [](const std::optional<std::array<double, 3>>& v) -> std::optional<glm::dvec3> {
        if (!v)
            return std::nullopt;
        return glm::dvec3((*v)[0], (*v)[1], (*v)[2]);
    };
    if (!camera.position && !camera.position_lonlat)
        throw Error("CameraParameters: give a position (position or position_lonlat)");
    checkParameter("CameraParameters::fov_y_degrees", camera.fov_y_degrees, lod::kCameraFovYRange);
    CameraPlacement placement;
    placement.position = vec(camera.position);
    placement.position_lonlat = vec(camera.position_lonlat);
    placement.above_ground = camera.above_ground;
    placement.look_at = vec(camera.look_at);
    placement.look_at_lonlat = vec(camera.look_at_lonlat);
    placement.heading_deg = camera.heading_degrees;
    placement.pitch_deg = camera.pitch_degrees;
    placement.exaggeration = camera.vertical_exaggeration;
    const ResolvedCamera resolved = resolveCameraPlacement(impl_->query, placement);
    glm::dvec3 target;
    if (resolved.look_at) {
        target = *resolved.look_at;
    } else {
        // The terrain's centre on its finest surface (mid-range where it keeps no height).
        const lod::TerrainFrame& f = impl_->query.georeference().frame();
        const glm::dvec2 centre(0.5 * f.extentX(), 0.5 * f.extentY());
        const HeightSample s = impl_->query.sample(centre, PointSpace::Local);
        const double z = s.on_raster && !s.nodata
                             ? s.height
                             : 0.5 * (impl_->info.min_height + impl_->info.max_height);
        target = glm::dvec3(centre, z);
    }
    if (target == *resolved.position)
        throw Error("CameraParameters: the look-at point is the camera position");
    CameraPose pose;
    pose.position = {resolved.position->x, resolved.position->y, resolved.position->z};
    pose.look_at = {target.x, target.y, target.z};
    pose.fov_y_degrees = camera.fov_y_degrees;
    return pose;
}

} // namespace ridge
