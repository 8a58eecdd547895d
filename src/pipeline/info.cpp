#include "ridge/pipeline/info.h"

#include "ridge/archive/archive_reader.h"

#include <algorithm>

namespace ridge {

ArchiveInfo readArchiveInfo(const std::string& archive_path)
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
    return info;
}

} // namespace ridge
