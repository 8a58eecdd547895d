// The public API's Terrain (<ridge/ridge.h>): an open archive, its description, and GL-free
// height queries and coordinate conversions over pipeline's HeightQuery and
// TerrainGeoreference.
#include "ridge/ridge.h"

#include "ridge/pipeline/height_query.h"


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

} // namespace

struct Terrain::Impl {
    // HeightQuery caches decoded patches, hence mutable: Terrain's queries are logically
    // const, and the API is thread-compatible (one thread at a time per Terrain).
    mutable HeightQuery query;
    TerrainInfo info;

    Impl(const std::string& path, size_t cache_patches)
        : query(path, cache_patches), info(describe(query.reader()))
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

const TerrainInfo& Terrain::info() const { return impl_->info; }

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

} // namespace ridge
