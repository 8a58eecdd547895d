#include "ridge/pipeline/height_query.h"

#include "ridge/core/error.h"
#include "ridge/core/parameter_check.h"

#include <algorithm>
#include <cmath>
#include <unordered_set>

namespace ridge {

namespace {

std::unique_ptr<archive::ArchiveReader> openArchive(const std::string& path)
{
    return std::make_unique<archive::ArchiveReader>(path);
}

// The level sample nearest to finest-sample coordinate `c` (clamped to [0, last]) along one
// axis: samples of the level sit every `step` finest samples, the last one clamped onto the
// last finest sample (pyramid_geometry.h). Ties go to the higher sample, as GDAL's ⌊P⌋ does at
// a pixel edge.
int nearestLevelSample(double c, int64_t step, int64_t last)
{
    const int64_t i0 = int64_t(c / double(step));
    const double p0 = double(i0 * step), p1 = double(std::min((i0 + 1) * step, last));
    return int(p1 - c <= c - p0 ? i0 + 1 : i0);
}

} // namespace

std::string_view resamplingName(QueryResampling resampling)
{
    return resampling == QueryResampling::Nearest ? "nearest" : "bilinear";
}

std::optional<QueryResampling> parseResampling(std::string_view name)
{
    if (name == "nearest")
        return QueryResampling::Nearest;
    if (name == "bilinear")
        return QueryResampling::Bilinear;
    return std::nullopt;
}

HeightQuery::HeightQuery(const std::string& archive_path, size_t cache_patches)
    : reader_(openArchive(archive_path)), georeference_(*reader_),
      quadtree_(lod::PatchQuadtree::fromArchive(*reader_)), loader_(*reader_, cache_patches),
      cache_patches_(std::max(cache_patches, size_t(reader_->geometry().levelCount()) + 1))
{
}

HeightQuery::~HeightQuery() = default;

int HeightQuery::checkedLevel(int level) const
{
    const int finest = reader_->geometry().finestLevel();
    if (level < 0)
        return finest;
    checkParameter("level", int64_t{level}, 0, finest);
    return level;
}

bool HeightQuery::place(glm::dvec2 point, PointSpace space, HeightSample& out) const
{
    const PyramidGeometry& g = reader_->geometry();
    // Through pixel/line, so that a sample centre given as pixel/line reads that sample exactly.
    out.pixel = georeference_.toPixel(point, space);
    out.local = space == PointSpace::Local ? point : georeference_.localOfPixel(out.pixel);
    // The raster is its pixels' area; a NaN-safe test (finite by now anyway).
    out.on_raster = out.pixel.x >= 0.0 && out.pixel.x <= double(g.width()) && out.pixel.y >= 0.0 &&
                    out.pixel.y <= double(g.height());
    return out.on_raster;
}

HeightQuery::Location HeightQuery::locate(glm::dvec2 pixel, int level,
                                          QueryResampling resampling) const
{
    const PyramidGeometry& g = reader_->geometry();
    const int cells = g.cells();
    const int64_t step = g.step(level);
    Location at;
    if (resampling == QueryResampling::Nearest) {
        int i = 0, j = 0; // the level sample
        if (step == 1) {
            // GDAL's pixel: ⌊P⌋, ⌊L⌋; the raster's far edges (P = width) belong to the last.
            i = std::min(int(std::floor(pixel.x)), g.width() - 1);
            j = std::min(int(std::floor(pixel.y)), g.height() - 1);
        } else {
            const double column = std::clamp(pixel.x - 0.5, 0.0, double(g.width() - 1));
            const double row = std::clamp(pixel.y - 0.5, 0.0, double(g.height() - 1));
            i = nearestLevelSample(column, step, g.width() - 1);
            j = nearestLevelSample(row, step, g.height() - 1);
        }
        // The covering patch: on a shared border the lower index (the sample is in both).
        const int px = std::min(i / cells, g.patchesX(level) - 1);
        const int py = std::min(j / cells, g.patchesY(level) - 1);
        at.patch = {level, px, py};
        at.u = i - px * cells;
        at.v = j - py * cells;
        return at;
    }
    // Finest sample coordinates on the surface (the outer half pixel clamps to the border),
    // then the level's: level samples sit every step(level) finest samples.
    const double column = std::clamp(pixel.x - 0.5, 0.0, double(g.width() - 1));
    const double row = std::clamp(pixel.y - 0.5, 0.0, double(g.height() - 1));
    const double u_level = column / double(step), v_level = row / double(step);
    // The covering patch: the one whose cells hold the point; on a shared border the lower
    // index (both give the same height). Clamped: the last sample lies on the last patch's
    // east/south border.
    const int px = std::min(int(u_level / cells), g.patchesX(level) - 1);
    const int py = std::min(int(v_level / cells), g.patchesY(level) - 1);
    at.patch = {level, px, py};
    const double u = u_level - double(px) * cells, v = v_level - double(py) * cells;
    at.u = std::min(int(u), cells - 1);
    at.v = std::min(int(v), cells - 1);
    at.fu = u - at.u;
    at.fv = v - at.v;
    return at;
}

size_t HeightQuery::workingSet(int level, size_t limit) const
{
    // first_of_[p + 1] counts the points in patch p of `level` (before the prefix sums).
    const PyramidGeometry& g = reader_->geometry();
    const int patches_x = g.patchesX(level);
    std::unordered_set<int64_t> patches;
    for (size_t p = 0; p + 1 < first_of_.size() && patches.size() <= limit; ++p) {
        if (first_of_[p + 1] == 0)
            continue;
        PatchId id{level, int(p % size_t(patches_x)), int(p / size_t(patches_x))};
        patches.insert(g.patchIndex(id));
        while (id.level > 0 && reader_->codec().needsParent(id.level) &&
               patches.insert(g.patchIndex(id.parent())).second)
            id = id.parent();
    }
    return patches.size();
}

std::shared_ptr<const PatchValidity> HeightQuery::sampleValidity(PatchId p)
{
    const int64_t key = reader_->geometry().patchIndex(p);
    if (const auto* hit = validity_.find(key))
        return *hit;
    auto validity = std::make_shared<const PatchValidity>(reader_->readValidity(p));
    validity_.insert(key, validity);
    return validity;
}

void HeightQuery::read(const Location& at, const stream::DecodedPatch& patch,
                       QueryResampling resampling, HeightSample& out)
{
    out.patch = at.patch;
    out.error_bound = reader_->record(at.patch).err;
    const int n = reader_->geometry().patchSize();
    auto code = [&](int a, int b) {
        return double(patch.codes[size_t(b) * size_t(n) + size_t(a)]);
    };
    const PatchSampleFlags& flags = patch.sample_flags;
    const bool stored = reader_->storesSampleFlags();
    if (resampling == QueryResampling::Nearest) {
        // No drawable-cell mask: every sample is data. Otherwise the sample's own validity.
        if (!patch.drawable_cells.empty() && !sampleValidity(at.patch)->sampleValid(at.u, at.v)) {
            out.nodata = true;
            out.nodata_fill = reader_->quantization().toMetres(code(at.u, at.v));
            return;
        }
        out.height = reader_->quantization().toMetres(code(at.u, at.v));
        out.water = stored ? flags.water(at.u, at.v) : out.height <= 0.0;
        out.filled = flags.filled(at.u, at.v);
        return;
    }
    // Kept nodata: the cell the point lies in is not drawn, so the terrain has no height here.
    const int cells = n - 1;
    // At a sample (fu = fv = 0) this is that sample's code exactly: the weights 0 and 1 make
    // no rounding.
    const int u0 = at.u, v0 = at.v;
    const double fu = at.fu, fv = at.fv;
    const double c = (code(u0, v0) * (1 - fu) + code(u0 + 1, v0) * fu) * (1 - fv) +
                     (code(u0, v0 + 1) * (1 - fu) + code(u0 + 1, v0 + 1) * fu) * fv;
    if (!patch.drawable_cells.empty() &&
        patch.drawable_cells[size_t(at.v) * size_t(cells) + size_t(at.u)] == 0) {
        out.nodata = true;
        out.nodata_fill = reader_->quantization().toMetres(c);
        return;
    }
    out.height = reader_->quantization().toMetres(c);
    if (!stored) {
        out.water = out.height <= 0.0;
        return;
    }
    if (flags.kind == PatchSampleFlags::Kind::None)
        return;
    const double weight[4] = {(1 - fu) * (1 - fv), fu * (1 - fv), (1 - fu) * fv, fu * fv};
    const int du[4] = {0, 1, 0, 1}, dv[4] = {0, 0, 1, 1};
    double water = 0.0;
    for (int k = 0; k < 4; ++k) {
        water += flags.water(u0 + du[k], v0 + dv[k]) ? weight[k] : 0.0;
        out.filled = out.filled || (weight[k] > 0.0 && flags.filled(u0 + du[k], v0 + dv[k]));
    }
    out.water = water >= 0.5;
}

HeightSample HeightQuery::sample(glm::dvec2 point, PointSpace space, int level,
                                 QueryResampling resampling)
{
    HeightSample out;
    out.level = checkedLevel(level);
    if (!place(point, space, out))
        return out;
    const Location at = locate(out.pixel, out.level, resampling);
    read(at, *loader_.load(at.patch), resampling, out);
    return out;
}

void HeightQuery::sampleBatch(std::span<const glm::dvec2> points, PointSpace space, int level,
                              QueryResampling resampling, std::span<HeightSample> out)
{
    if (out.size() != points.size())
        throw Error("height query: " + std::to_string(out.size()) + " results for " +
                    std::to_string(points.size()) + " points: the output must have one a point");
    sampleEach(points, space, level, resampling,
               [&](size_t k, const HeightSample& s) { out[k] = s; });
}

void HeightQuery::sampleEach(std::span<const glm::dvec2> points, PointSpace space, int level,
                             QueryResampling resampling,
                             const std::function<void(size_t, const HeightSample&)>& emit)
{
    level = checkedLevel(level);
    // What the archive lacks fails the whole batch, by name; bad points fail alone.
    if ((space == PointSpace::Crs || space == PointSpace::LonLat) &&
        !georeference_.hasGeotransform())
        throw Error(reader_->path() + ": the archive has no geotransform: give points in " +
                    "local or pixel coordinates");
    if (space == PointSpace::LonLat && !georeference_.hasCrs())
        throw Error(reader_->path() + ": the archive has no CRS (the source was not "
                                      "georeferenced): longitude/latitude cannot be converted");
    const PyramidGeometry& g = reader_->geometry();
    const int patches_x = g.patchesX(level);
    const size_t level_patches = size_t(g.patchCount(level));
    // Point indices are 32 bits: slices of at most 2^32 − 1 points.
    constexpr size_t kSlice = (size_t(1) << 32) - 1;
    for (size_t first = 0; first < points.size(); first += kSlice) {
        const size_t count = std::min(kSlice, points.size() - first);
        // Place every point; answer those off the raster, note the others' patch (its index
        // within the level).
        pixels_.resize(count);
        patch_of_.resize(count);
        for (size_t k = 0; k < count; ++k) {
            HeightSample s;
            s.level = level;
            bool on_raster = false;
            try {
                on_raster = place(points[first + k], space, s);
            } catch (const Error&) {
                s = HeightSample{};
                s.level = level;
                s.invalid_point = true;
            }
            if (!on_raster) {
                emit(first + k, s);
                patch_of_[k] = kNoPatch;
                continue;
            }
            pixels_[k] = s.pixel;
            const PatchId patch = locate(s.pixel, level, resampling).patch;
            patch_of_[k] = uint32_t(size_t(patch.y) * size_t(patches_x) + size_t(patch.x));
        }
        // The order to read them in. When the patches they touch, with the ancestors their
        // decodes load, fit in the cache, input order: in an LRU no patch of that working
        // set is evicted before its last use, and memory is walked in order. Otherwise patch
        // by patch (a counting sort, linear in points and patches), so that each patch is
        // decoded once however small the cache.
        first_of_.assign(level_patches + 1, 0);
        for (size_t k = 0; k < count; ++k)
            if (patch_of_[k] != kNoPatch)
                ++first_of_[patch_of_[k] + 1];
        order_.clear();
        if (workingSet(level, cache_patches_) <= cache_patches_) {
            for (size_t k = 0; k < count; ++k)
                if (patch_of_[k] != kNoPatch)
                    order_.push_back(uint32_t(k));
        } else {
            for (size_t p = 0; p < level_patches; ++p)
                first_of_[p + 1] += first_of_[p];
            order_.resize(first_of_[level_patches]);
            for (size_t k = 0; k < count; ++k)
                if (patch_of_[k] != kNoPatch)
                    order_[first_of_[patch_of_[k]]++] = uint32_t(k);
        }
        std::shared_ptr<const stream::DecodedPatch> patch;
        uint32_t loaded = kNoPatch;
        for (const uint32_t k : order_) {
            HeightSample s;
            s.level = level;
            s.on_raster = true;
            s.pixel = pixels_[k];
            s.local = space == PointSpace::Local ? points[first + k]
                                                 : georeference_.localOfPixel(s.pixel);
            const Location at = locate(s.pixel, level, resampling);
            if (patch_of_[k] != loaded) {
                patch = loader_.load(at.patch);
                loaded = patch_of_[k];
            }
            read(at, *patch, resampling, s);
            emit(first + k, s);
        }
    }
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
