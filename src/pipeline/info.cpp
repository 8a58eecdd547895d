#include "ridge/pipeline/info.h"

#include "ridge/archive/archive_reader.h"
#include "ridge/core/error.h"
#include "ridge/io/crs_summary.h"
#include "ridge/pipeline/terrain_georeference.h"

#include <algorithm>

namespace ridge {

namespace {

// gdalinfo's five points, in its order.
std::vector<CornerInfo> cornersOf(const archive::ArchiveReader& reader, std::string& note)
{
    const TerrainGeoreference geo(reader);
    if (!geo.hasGeotransform())
        return {};
    const double w = reader.geometry().width(), h = reader.geometry().height();
    std::vector<CornerInfo> corners = {{"Upper Left", 0, 0},
                                       {"Lower Left", 0, h},
                                       {"Upper Right", w, 0},
                                       {"Lower Right", w, h},
                                       {"Center", w / 2, h / 2}};
    for (CornerInfo& c : corners) {
        const glm::dvec2 local = geo.toLocal({c.pixel, c.line}, PointSpace::Pixel);
        const glm::dvec2 crs = geo.fromLocal(local, PointSpace::Crs);
        c.x = crs.x;
        c.y = crs.y;
        if (!geo.hasCrs()) {
            note = "no CRS";
            continue;
        }
        try {
            const glm::dvec2 lon_lat = geo.fromLocal(local, PointSpace::LonLat);
            c.longitude = lon_lat.x;
            c.latitude = lon_lat.y;
            c.has_lon_lat = true;
        } catch (const Error& e) {
            note = e.what(); // a corner outside the projection's domain, or no transformation
        }
    }
    return corners;
}

ByteAccount accountBytes(const archive::ArchiveReader& reader)
{
    const archive::Header& h = reader.header();
    const PyramidGeometry& g = reader.geometry();
    ByteAccount a;
    a.header = archive::kHeaderSize;
    a.index = reader.fileSize() - h.index_offset; // the reader checked it lies in the file
    a.metadata = h.metadata_size;
    a.codec_tables = h.codec_tables_size;
    a.levels.resize(size_t(g.levelCount()));
    for (int64_t i = 0; i < g.patchCount(); ++i) {
        const PatchId p = g.patchAt(i);
        archive::BlobParts parts;
        reader.payloadOffset(p, reader.readBlob(p), nullptr, nullptr, &parts);
        ByteAccount::Level& l = a.levels[size_t(p.level)];
        l.block_errors += parts.block_errors;
        l.validity += parts.validity;
        l.sample_flags += parts.sample_flags;
        l.payload += parts.payload;
    }
    return a;
}

} // namespace

uint64_t ByteAccount::total() const
{
    uint64_t sum = header + index + metadata + codec_tables;
    for (const Level& l : levels)
        sum += l.block_errors + l.validity + l.sample_flags + l.payload;
    return sum;
}

ArchiveInfo readArchiveInfo(const std::string& archive_path, bool account_bytes)
{
    const archive::ArchiveReader reader(archive_path);
    const archive::Header& h = reader.header();
    const PyramidGeometry& g = reader.geometry();
    ArchiveInfo info;
    info.path = archive_path;
    info.format_version = h.version;
    info.file_bytes = reader.fileSize();
    info.width = g.width();
    info.height = g.height();
    info.patch_size = g.patchSize();
    info.level_count = g.levelCount();
    info.block_cells = static_cast<int>(h.block_cells);
    info.block_levels = static_cast<int>(h.block_levels);
    info.patch_count = g.patchCount();
    info.codec = reader.codec().name();
    info.filter = filterName(reader.filter());
    info.height_scale = h.height_scale;
    info.height_offset = h.height_offset;
    info.quantization_error = h.quantization_error;
    info.spacing_x = h.spacing_x;
    info.spacing_y = h.spacing_y;
    info.metadata_json = reader.metadataJson();
    info.metadata = reader.metadata();
    const archive::PatchRecord& root = reader.record({0, 0, 0});
    info.min_height = root.min_height;
    info.max_height = root.max_height;
    for (int l = 0; l < g.levelCount(); ++l) {
        LevelInfo li;
        li.level = l;
        li.step = g.step(l);
        li.width = g.validLevelWidth(l);
        li.height = g.validLevelHeight(l);
        li.patches_x = g.patchesX(l);
        li.patches_y = g.patchesY(l);
        li.level_bound = reader.levelErrorBound(l);
        for (int64_t i = g.firstPatchIndex(l); i < g.firstPatchIndex(l) + g.patchCount(l); ++i) {
            const archive::PatchRecord& r = reader.index()[i];
            li.bytes += r.size;
            li.max_err = std::max(li.max_err, double(r.err));
            li.max_err_appr = std::max(li.max_err_appr, double(r.err_appr));
        }
        info.levels.push_back(li);
    }
    info.corners = cornersOf(reader, info.lon_lat_note);
    if (account_bytes)
        info.bytes = accountBytes(reader);

    const archive::ArchiveMetadata& meta = reader.metadata();
    info.band = meta.source.band.value_or(1);
    info.data_type = meta.source.data_type;
    info.nodata = meta.source.nodata;
    info.quantization_step = h.height_scale;
    info.exact = meta.source.exact;
    info.vertical_datum = meta.georeference.vertical_datum;
    try {
        const io::CrsSummary crs = io::summarizeCrs(meta.georeference.crs_wkt, archive_path);
        info.crs_name = crs.name;
        info.epsg = crs.epsg;
        if (!info.vertical_datum && crs.vertical.known())
            info.vertical_datum = archive::VerticalDatumMetadata{
                crs.vertical.name, crs.vertical.epsg, crs.vertical.origin};
    } catch (const Error& e) {
        info.crs_note = e.what(); // the WKT PROJ cannot read is still printed whole by --json
    }
    return info;
}

} // namespace ridge
