// The public API's Terrain (<ridge/ridge.h>): an open archive, its description, and GL-free
// height queries and coordinate conversions over pipeline's HeightQuery and
// TerrainGeoreference.
#include "ridge/ridge.h"

#include "ridge/archive/archive_reader.h"


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
    archive::ArchiveReader reader;
    TerrainInfo info;
    Impl(const std::string& path, size_t) : reader(path), info(describe(reader)) {}
};

Terrain::Terrain(const std::string& archive_path, size_t cache_patches)
    : impl_(std::make_unique<Impl>(archive_path, cache_patches))
{
}
Terrain::~Terrain() = default;
Terrain::Terrain(Terrain&&) noexcept = default;
Terrain& Terrain::operator=(Terrain&&) noexcept = default;

const TerrainInfo& Terrain::info() const { return impl_->info; }

} // namespace ridge
