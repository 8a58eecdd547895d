// `ridge verify --source`: every level's surface against the source raster on every valid
// sample (the end-to-end bound Err(P), and δ_l at the level's own samples), and the finest
// validity against the source's voids in both directions.
#include "verify_internal.h"

#include "ridge/core/error.h"
#include "ridge/io/raster_source.h"

#include <algorithm>
#include <cmath>
#include <optional>

namespace ridge::verify_detail {

namespace {

using archive::ArchiveReader;

// Per-thread accumulator of one level's source comparison.
struct LevelAccumulator {
    int64_t samples = 0, violations = 0, level_samples = 0, level_violations = 0;
    double max_error = 0.0, sum_sq = 0.0, max_level_error = 0.0;
    void merge(const LevelAccumulator& o)
    {
        samples += o.samples;
        violations += o.violations;
        level_samples += o.level_samples;
        level_violations += o.level_violations;
        max_error = std::max(max_error, o.max_error);
        sum_sq += o.sum_sq;
        max_level_error = std::max(max_level_error, o.max_level_error);
    }
};

// The patches of one axis that contain level coordinate i + t (t in [0, 1)): two on a shared
// border, else one.
std::pair<int, int> patchSpan(int i, bool on_sample, int cells, int patches)
{
    const int hi = std::min(i / cells, patches - 1);
    const int lo = on_sample && i % cells == 0 && i > 0 ? std::min(i / cells - 1, hi) : hi;
    return {lo, hi};
}

// Whether every patch of `level` in [x0, x1] × [y0, y1] decoded.
bool decodedAround(const PyramidGeometry& g, int level, const DecodedLevel& decoded, int x0, int x1,
                   int y0, int y1)
{
    for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x)
            if (!decoded.patchDecoded(g, level, x, y))
                return false;
    return true;
}

// Compares one source row with the bilinear surface of one level. A sample on a shared patch
// border must satisfy the bound of every patch that covers it, so it is checked against the
// smallest of their Err(P).
void compareRow(const ArchiveReader& reader, int level, const DecodedLevel& decoded,
                bool exact_levels, int y, const double* source, LevelAccumulator& acc)
{
    const CodeGrid& grid = decoded.grid;
    const PyramidGeometry& g = reader.geometry();
    const HeightQuantization q = reader.quantization();
    const int64_t step = g.step(level);
    const int cells = g.cells();
    const double inv = 1.0 / double(step);
    const int j = static_cast<int>(y / step);
    const double ty = (y - j * step) * inv;
    const int j1 = std::min(j + 1, grid.height - 1);
    const auto [py_lo, py_hi] = patchSpan(j, ty == 0, cells, g.patchesY(level));
    const double delta = reader.levelErrorBound(level);
    const bool on_level_row = y % step == 0;
    for (int x = 0; x < g.width(); ++x) {
        const double h = source[x];
        if (std::isnan(h))
            continue;
        const int i = static_cast<int>(x / step);
        const double tx = (x - i * step) * inv;
        const int i1 = std::min(i + 1, grid.width - 1);
        const auto [px_lo, px_hi] = patchSpan(i, tx == 0, cells, g.patchesX(level));
        // Only where every patch the surface reads from decoded (a failure is reported once).
        if (!decodedAround(g, level, decoded, px_lo,
                           std::max(px_hi, std::min(i1 / cells, g.patchesX(level) - 1)), py_lo,
                           std::max(py_hi, std::min(j1 / cells, g.patchesY(level) - 1))))
            continue;
        const double top = grid.at(i, j) * (1 - tx) + grid.at(i1, j) * tx;
        const double bottom = grid.at(i, j1) * (1 - tx) + grid.at(i1, j1) * tx;
        const double surface = q.toMetres(top * (1 - ty) + bottom * ty);
        const double e = std::fabs(surface - h);
        const double slack = 1e-9 * std::max(1.0, std::fabs(h)); // double rounding only
        double bound = INFINITY;
        for (int py = py_lo; py <= py_hi; ++py)
            for (int px = px_lo; px <= px_hi; ++px)
                bound = std::min(bound, double(reader.record({level, px, py}).err));
        acc.samples++;
        acc.sum_sq += e * e;
        acc.max_error = std::max(acc.max_error, e);
        if (e > bound + slack)
            acc.violations++;
        if (exact_levels && on_level_row && x % step == 0) {
            acc.level_samples++;
            acc.max_level_error = std::max(acc.max_level_error, e);
            if (e > delta + slack)
                acc.level_violations++;
        }
    }
}

// The voids of `source_void` (W × H, 1 = void) 8-connected to the raster border (ingest's
// rule for --fill-voids interior, restated here so that verify checks the ingest rather than
// repeating it): 1 at each such void. Memory: the result and a stack of at most the voids.
std::vector<uint8_t> borderConnectedVoids(const std::vector<uint8_t>& source_void, int w, int h)
{
    std::vector<uint8_t> connected(source_void.size(), 0);
    std::vector<int64_t> stack;
    auto push = [&](int64_t x, int64_t y) {
        if (x < 0 || y < 0 || x >= w || y >= h)
            return;
        const size_t k = static_cast<size_t>(y) * w + static_cast<size_t>(x);
        if (source_void[k] && !connected[k]) {
            connected[k] = 1;
            stack.push_back(static_cast<int64_t>(k));
        }
    };
    for (int x = 0; x < w; ++x) {
        push(x, 0);
        push(x, h - 1);
    }
    for (int y = 0; y < h; ++y) {
        push(0, y);
        push(w - 1, y);
    }
    while (!stack.empty()) {
        const int64_t k = stack.back();
        stack.pop_back();
        const int64_t x = k % w, y = k / w;
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx)
                push(x + dx, y + dy);
    }
    return connected;
}

// The finest validity against the source's voids, both ways (docs/FORMAT.md, "Validity
// mask": a finest sample is valid iff the source has data there or the build filled the
// void, which --fill-voids all does for every void and interior for those not 8-connected to
// the border). A valid sample over a kept void would be drawn and exported as an invented
// height; an invalid one over data or over a filled void would be a hole.
void compareVoids(const ArchiveReader& reader, const std::vector<uint8_t>& source_void,
                  const std::vector<uint8_t>& finest_valid, ProblemList& problems)
{
    const PyramidGeometry& g = reader.geometry();
    const std::string& mode = reader.metadata().source.fill_voids;
    std::vector<uint8_t> border;
    if (mode == "interior")
        border = borderConnectedVoids(source_void, g.width(), g.height());
    int64_t over_data = 0, over_kept_void = 0, over_filled_void = 0;
    for (size_t k = 0; k < source_void.size(); ++k) {
        const bool is_void = source_void[k] != 0;
        const bool filled = is_void && (mode == "all" || (mode == "interior" && !border[k]));
        const bool expected_valid = !is_void || filled;
        const bool valid = finest_valid[k] != 0;
        if (valid == expected_valid)
            continue;
        if (!is_void)
            ++over_data;
        else if (valid)
            ++over_kept_void;
        else
            ++over_filled_void;
    }
    const std::string path = reader.path() + ": ";
    if (over_data)
        problems.add(path + std::to_string(over_data) +
                     " finest samples are kept as nodata where the source has data");
    if (over_kept_void)
        problems.add(path + std::to_string(over_kept_void) +
                     " finest samples are valid (drawn, exported as heights) where the source "
                     "has voids that --fill-voids " +
                     mode + " keeps as nodata");
    if (over_filled_void)
        problems.add(path + std::to_string(over_filled_void) +
                     " finest samples are kept as nodata where the source has voids that "
                     "--fill-voids " +
                     mode + " fills");
}

// Filled flags exactly where the build filled a source void (a void the archive keeps valid),
// water at least where the sea level says so on measured samples, and none beyond it unless a
// water layer was given (which only it can confirm). `finest_valid` may be empty (all valid).
void compareFlags(const ArchiveReader& reader, const std::vector<uint8_t>& source_void,
                  const std::vector<uint8_t>& source_water,
                  const std::vector<uint8_t>& finest_valid,
                  const std::vector<uint8_t>& finest_flags, ProblemList& problems)
{
    const bool layer = reader.metadata().water.layer.has_value();
    int64_t filled_wrong = 0, water_missing = 0, water_extra = 0;
    for (size_t k = 0; k < finest_flags.size(); ++k) {
        const bool valid = finest_valid.empty() || finest_valid[k];
        const bool filled = (finest_flags[k] & kSampleFilled) != 0;
        const bool water = (finest_flags[k] & kSampleWater) != 0;
        filled_wrong += filled != (valid && source_void[k]);
        if (!valid || source_void[k])
            continue; // a filled height is judged by its code, which the source does not have
        water_missing += source_water[k] && !water;
        water_extra += !source_water[k] && water && !layer;
    }
    const std::string& path = reader.path();
    if (filled_wrong)
        problems.add(path + ": " + std::to_string(filled_wrong) +
                     " finest samples are flagged filled where the build filled no void, or not "
                     "flagged where it did");
    if (water_missing)
        problems.add(path + ": " + std::to_string(water_missing) +
                     " finest samples at or below the sea level in the source are not flagged "
                     "water");
    if (water_extra)
        problems.add(path + ": " + std::to_string(water_extra) +
                     " finest samples are flagged water above the sea level, and the archive "
                     "names no water layer");
}

} // namespace

void compareWithSource(const ArchiveReader& reader, const std::vector<DecodedLevel>& levels,
                       const std::vector<uint8_t>& finest_valid,
                       const std::vector<uint8_t>& finest_flags, const std::string& source_path,
                       VerifyReport& report, ProblemList& problems, const Progress& progress)
{
    // The source's values map to metres as they did when the archive was built.
    io::IngestOptions options;
    options.z_scale = reader.metadata().build.z_scale;
    options.z_offset = reader.metadata().build.z_offset;
    options.band = reader.metadata().source.band.value_or(1); // the band the archive was built from
    // Heights shifted to the ellipsoid at build are compared shifted the same way.
    options.vertical_shift = io::VerticalShift::None;
    if (const auto& shift = reader.metadata().build.vertical_shift) {
        options.vertical_shift = io::VerticalShift::Ellipsoid;
        options.vertical_datum = "EPSG:" + std::to_string(shift->from_epsg);
    }
    io::ReferenceRaster source(source_path, options);
    const PyramidGeometry& g = reader.geometry();
    if (source.width() != g.width() || source.height() != g.height()) {
        problems.add(source_path + ": size " + std::to_string(source.width()) + "x" +
                     std::to_string(source.height()) + " differs from the archive's " +
                     std::to_string(g.width()) + "x" + std::to_string(g.height()));
        return;
    }
    const int level_count = g.levelCount();
    const bool decimated = reader.filter() == PyramidFilter::Decimate;
    std::vector<LevelAccumulator> totals(level_count);
    std::vector<uint8_t> source_void(static_cast<size_t>(g.width()) * g.height());
    // 1 where the source's measured height is at or below the archive's sea level.
    std::vector<uint8_t> source_water(source_void.size(), 0);
    const std::optional<double> sea_level = reader.metadata().water.sea_level;
    constexpr int kStrip = 128;
    std::vector<double> strip(static_cast<size_t>(kStrip) * g.width());
    std::vector<double> source_heights(strip.size()); // before a vertical shift: for water
    for (int y0 = 0; y0 < g.height(); y0 += kStrip) {
        const int rows = std::min(kStrip, g.height() - y0);
        source.readRows(y0, rows, strip.data(), source_heights.data());
        const size_t first = static_cast<size_t>(y0) * g.width();
        for (size_t k = 0; k < static_cast<size_t>(rows) * g.width(); ++k) {
            source_void[first + k] = std::isnan(strip[k]) ? 1 : 0;
            source_water[first + k] = sea_level && source_heights[k] <= *sea_level; // NaN: no
            report.source_voids += source_void[first + k];
            if (!finest_valid.empty())
                report.nodata_samples += finest_valid[first + k] == 0;
        }
#pragma omp parallel
        {
            std::vector<LevelAccumulator> local(level_count);
#pragma omp for schedule(static)
            for (int r = 0; r < rows; ++r)
                for (int l = 0; l < level_count; ++l)
                    compareRow(reader, l, levels[l], decimated || l == level_count - 1, y0 + r,
                               strip.data() + static_cast<size_t>(r) * g.width(), local[l]);
#pragma omp critical
            for (int l = 0; l < level_count; ++l)
                totals[l].merge(local[l]);
        }
        reportProgress(progress, double(y0 + rows) / g.height());
    }
    if (!finest_valid.empty())
        compareVoids(reader, source_void, finest_valid, problems);
    if (!finest_flags.empty())
        compareFlags(reader, source_void, source_water, finest_valid, finest_flags, problems);
    for (int l = 0; l < level_count; ++l) {
        LevelVerifyReport& lr = report.levels[l];
        const LevelAccumulator& t = totals[l];
        lr.samples = t.samples;
        lr.max_error = t.max_error;
        lr.rms_error = t.samples ? std::sqrt(t.sum_sq / double(t.samples)) : 0.0;
        lr.bound_violations = t.violations;
        lr.level_samples = t.level_samples;
        lr.max_level_error = t.max_level_error;
        lr.level_bound = reader.levelErrorBound(l);
        lr.level_violations = t.level_violations;
        if (t.violations)
            problems.add(reader.path() + ": level " + std::to_string(l) + ": " +
                         std::to_string(t.violations) +
                         " source samples deviate more than their patch's Err(P)");
        if (t.level_violations)
            problems.add(reader.path() + ": level " + std::to_string(l) + ": " +
                         std::to_string(t.level_violations) +
                         " level samples deviate more than δ_l");
    }
    report.source_checked = true;
}

} // namespace ridge::verify_detail
