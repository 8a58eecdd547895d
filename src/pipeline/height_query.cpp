#include "ridge/pipeline/height_query.h"

#include "ridge/core/error.h"
#include "ridge/core/parameter_check.h"

#include <algorithm>
#include <cmath>

namespace ridge {

namespace {

std::unique_ptr<archive::ArchiveReader> openArchive(const std::string& path)
{
    return std::make_unique<archive::ArchiveReader>(path);
}

} // namespace

HeightQuery::HeightQuery(const std::string& archive_path, size_t cache_patches)
    : reader_(openArchive(archive_path)), georeference_(*reader_),
      quadtree_(lod::PatchQuadtree::fromArchive(*reader_)), loader_(*reader_, cache_patches)
{
}

HeightQuery::~HeightQuery() = default;

HeightSample HeightQuery::sample(glm::dvec2 point, PointSpace space, int level)
{
    const PyramidGeometry& g = reader_->geometry();
    if (level < 0)
        level = g.finestLevel();
    checkParameter("level", int64_t{level}, 0, g.finestLevel());
    HeightSample out;
    out.level = level;
    // Through pixel/line, so that a sample centre given as pixel/line reads that sample exactly.
    out.pixel = georeference_.toPixel(point, space);
    out.local = space == PointSpace::Local ? point : georeference_.localOfPixel(out.pixel);
    // The raster is its pixels' area; a NaN-safe test (finite by now anyway).
    out.on_raster = out.pixel.x >= 0.0 && out.pixel.x <= double(g.width()) &&
                    out.pixel.y >= 0.0 && out.pixel.y <= double(g.height());
    if (!out.on_raster)
        return out;

    // Finest sample coordinates on the surface (the outer half pixel clamps to the border),
    // then the level's: level samples sit every step(level) finest samples.
    const double column = std::clamp(out.pixel.x - 0.5, 0.0, double(g.width() - 1));
    const double row = std::clamp(out.pixel.y - 0.5, 0.0, double(g.height() - 1));
    const double step = double(g.step(level));
    const double i = column / step, j = row / step;
    const int cells = g.cells();
    // The covering patch: the one whose cells hold the point; on a shared border the lower
    // index (both give the same height). Clamped: the last sample lies on the last patch's
    // east/south border.
    const int px = std::min(int(i / cells), g.patchesX(level) - 1);
    const int py = std::min(int(j / cells), g.patchesY(level) - 1);
    out.patch = {level, px, py};
    const double u = i - double(px) * cells, v = j - double(py) * cells;
    const int u0 = std::min(int(u), cells - 1), v0 = std::min(int(v), cells - 1);
    const double fu = u - u0, fv = v - v0;

    const std::shared_ptr<const stream::DecodedPatch> patch = loader_.load(out.patch);
    out.error_bound = reader_->record(out.patch).err;
    // Kept nodata: the cell the point lies in is not drawn, so the terrain has no height here.
    if (!patch->drawable_cells.empty() &&
        patch->drawable_cells[size_t(v0) * size_t(cells) + size_t(u0)] == 0) {
        out.nodata = true;
        return out;
    }
    const int n = g.patchSize();
    auto code = [&](int a, int b) {
        return double(patch->codes[size_t(b) * size_t(n) + size_t(a)]);
    };
    // At a sample (fu = fv = 0) this is that sample's code exactly: the weights 0 and 1 make
    // no rounding.
    const double c = (code(u0, v0) * (1 - fu) + code(u0 + 1, v0) * fu) * (1 - fv) +
                     (code(u0, v0 + 1) * (1 - fu) + code(u0 + 1, v0 + 1) * fu) * fv;
    out.height = reader_->quantization().toMetres(c);
    return out;
}

std::optional<lod::SelectedPatch> HeightQuery::drawnPatch(const lod::Camera& camera,
                                                          const lod::SelectionSettings& settings,
                                                          glm::dvec2 local) const
{
    checkParameters("local point", &local.x, 2, ValueRange::any());
    const lod::Selection selection = quadtree_.select(camera, settings);
    // Selected patches tile the visible extent without overlap; a point on a shared border
    // is in two, which draw the same surface there, so the first will do.
    for (const lod::SelectedPatch& s : selection.patches) {
        const lod::Box box = quadtree_.box(s.id);
        if (local.x >= box.min.x && local.x <= box.max.x && local.y >= box.min.y &&
            local.y <= box.max.y)
            return s;
    }
    return std::nullopt;
}

} // namespace ridge
