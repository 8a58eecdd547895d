#include "ridge/pipeline/verify.h"

#include "ridge/pipeline/level_decoder.h"

#include "ridge/archive/archive_reader.h"
#include "ridge/core/error.h"
#include "ridge/io/raster_source.h"
#include "ridge/pyramid/tessellation_block_errors.h"

#include <algorithm>
#include <cmath>
#include <mutex>

namespace ridge {

namespace {

using archive::ArchiveReader;

// Collects problems from parallel loops; keeps the first kMaxProblems.
class ProblemList {
public:
    explicit ProblemList(std::vector<std::string>& out) : out_(out) {}
    void add(std::string problem)
    {
        std::lock_guard lock(mutex_);
        if (out_.size() < kMaxProblems)
            out_.push_back(std::move(problem));
        else
            ++dropped_;
    }
    void finish()
    {
        if (dropped_)
            out_.push_back("... and " + std::to_string(dropped_) + " more problems");
    }

private:
    static constexpr size_t kMaxProblems = 100;
    std::vector<std::string>& out_;
    std::mutex mutex_;
    size_t dropped_ = 0;
};

// A decoded patch's right column and bottom row, compared later with the neighbours that own
// those samples (patches write only their own samples, so the loop stays race-free).
struct PatchBorders {
    std::vector<uint16_t> right;
    std::vector<uint16_t> bottom;
    bool decoded = false;
};

// Checks one decoded patch's stored metadata against its samples and stored λ (what the
// reader cannot check without decoding; the fields themselves were checked at open).
void checkPatchMetadata(const ArchiveReader& reader, PatchId p, const uint16_t* codes,
                        const std::vector<float>& stored, ProblemList& problems)
{
    const archive::PatchRecord& r = reader.record(p);
    const int n = reader.geometry().patchSize();
    const HeightQuantization q = reader.quantization();
    const auto [lo, hi] = std::minmax_element(codes, codes + static_cast<size_t>(n) * n);
    if (q.toMetres(*lo) < r.min_height || q.toMetres(*hi) > r.max_height)
        problems.add(reader.describe(p) + ": stored min/max do not bound its samples");

    const TessellationBlockLayout layout = reader.blockLayout();
    std::vector<float> computed(layout.valuesPerPatch());
    computeTessellationBlockErrors(codes, layout, computed.data());
    for (size_t i = 0; i < computed.size(); ++i) {
        if (stored[i] < computed[i] * q.scale * (1 - 1e-6)) {
            problems.add(reader.describe(p) + ": stored tessellation block error is below the recomputed one");
            break;
        }
    }
}

// Decodes all patches of a level into `grid`, checking each; returns the level's largest Err.
// The grid covers whole patches (padding included) so the next level can take its parents
// from it; `parents` is the previous level's grid (progressive codecs), else null.
// `valid`, when given, receives the patches' sample validity in the grid's layout (1 = data).
double decodeAndCheckLevel(const ArchiveReader& reader, int level, CodeGrid& grid,
                           const CodeGrid* parents, ProblemList& problems,
                           std::vector<uint8_t>* valid = nullptr)
{
    const PyramidGeometry& g = reader.geometry();
    const int n = g.patchSize(), cells = g.cells();
    const int nx = g.patchesX(level), ny = g.patchesY(level);
    grid.width = nx * cells + 1;
    grid.height = ny * cells + 1;
    grid.codes.assign(static_cast<size_t>(grid.width) * grid.height, 0);
    if (valid)
        valid->assign(grid.codes.size(), 1);
    std::vector<PatchBorders> borders(static_cast<size_t>(nx) * ny);

#pragma omp parallel for schedule(dynamic, 1)
    for (int64_t k = 0; k < int64_t{nx} * ny; ++k) {
        const PatchId p{level, static_cast<int>(k % nx), static_cast<int>(k / nx)};
        std::vector<uint16_t> codes(static_cast<size_t>(n) * n), parent;
        std::vector<float> block_errors;
        PatchValidity validity; // decodeBlob checks the mask on the way
        if (parents) {
            parent.resize(codes.size());
            copyPatchFromGrid(*parents, p.x / 2 * cells, p.y / 2 * cells, n, parent.data());
        }
        try {
            reader.decodeBlob(p, reader.readBlob(p), codes.data(),
                              parents ? parent.data() : nullptr, &block_errors, &validity);
            checkPatchMetadata(reader, p, codes.data(), block_errors, problems);
        } catch (const Error& e) {
            problems.add(e.what());
            continue;
        }
        // Own samples: [i0, i0+cells) x [j0, j0+cells), plus the far border on the last patch.
        const int i0 = p.x * cells, j0 = p.y * cells;
        const int ie = std::min(grid.width, i0 + (p.x == nx - 1 ? cells + 1 : cells));
        const int je = std::min(grid.height, j0 + (p.y == ny - 1 ? cells + 1 : cells));
        for (int j = j0; j < je; ++j)
            for (int i = i0; i < ie; ++i) {
                grid.at(i, j) = codes[static_cast<size_t>(j - j0) * n + (i - i0)];
                if (valid)
                    (*valid)[static_cast<size_t>(j) * grid.width + i] = validity.sampleValid(i - i0, j - j0);
            }
        PatchBorders& b = borders[k];
        b.decoded = true;
        for (int t = 0; t < n; ++t) {
            b.right.push_back(codes[static_cast<size_t>(t) * n + cells]);
            b.bottom.push_back(codes[static_cast<size_t>(cells) * n + t]);
        }
    }

    // Shared borders: a patch's right column / bottom row must equal the samples written by
    // the patches that own them (skipping owners that failed to decode; they are reported).
    auto ownerDecoded = [&](int i, int j) {
        const int ox = std::min(i / cells, nx - 1), oy = std::min(j / cells, ny - 1);
        return borders[static_cast<size_t>(oy) * nx + ox].decoded;
    };
    double max_err = 0.0;
    for (int64_t k = 0; k < int64_t{nx} * ny; ++k) {
        const PatchId p{level, static_cast<int>(k % nx), static_cast<int>(k / nx)};
        max_err = std::max(max_err, double(reader.record(p).err));
        const PatchBorders& b = borders[k];
        if (!b.decoded)
            continue;
        const int i0 = p.x * cells, j0 = p.y * cells;
        bool right_ok = true, bottom_ok = true;
        for (int t = 0; t < n; ++t) {
            const int ir = i0 + cells, jr = j0 + t; // right column sample
            if (p.x + 1 < nx && jr < grid.height && ownerDecoded(ir, jr))
                right_ok &= grid.at(ir, jr) == b.right[t];
            const int ib = i0 + t, jb = j0 + cells; // bottom row sample
            if (p.y + 1 < ny && ib < grid.width && ownerDecoded(ib, jb))
                bottom_ok &= grid.at(ib, jb) == b.bottom[t];
        }
        if (!right_ok)
            problems.add(reader.describe(p) + ": right border differs from its east neighbour");
        if (!bottom_ok)
            problems.add(reader.describe(p) + ": bottom border differs from its south neighbour");
    }
    return max_err;
}

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

// Compares one source row with the bilinear surface of one level. A sample on a shared patch
// border must satisfy the bound of every patch that covers it, so it is checked against the
// smallest of their Err(P).
void compareRow(const ArchiveReader& reader, int level, const CodeGrid& grid, bool exact_levels,
                int y, const double* source, LevelAccumulator& acc)
{
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
        const double top = grid.at(i, j) * (1 - tx) + grid.at(i1, j) * tx;
        const double bottom = grid.at(i, j1) * (1 - tx) + grid.at(i1, j1) * tx;
        const double surface = q.toMetres(top * (1 - ty) + bottom * ty);
        const double e = std::fabs(surface - h);
        const double slack = 1e-9 * std::max(1.0, std::fabs(h)); // double rounding only
        const auto [px_lo, px_hi] = patchSpan(i, tx == 0, cells, g.patchesX(level));
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

// `finest_valid`: the finest level's validity (decodeAndCheckLevel's layout).
void compareWithSource(const ArchiveReader& reader, const std::vector<CodeGrid>& levels,
                       const std::vector<uint8_t>& finest_valid, const std::string& source_path,
                       VerifyReport& report, ProblemList& problems, const Progress& progress)
{
    // The source's values map to metres as they did when the archive was built.
    io::IngestOptions options;
    options.z_scale = reader.metadata().build.z_scale;
    options.z_offset = reader.metadata().build.z_offset;
    options.band = reader.metadata().source.band.value_or(1); // the band the archive was built from
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
    constexpr int kStrip = 128;
    std::vector<double> strip(static_cast<size_t>(kStrip) * g.width());
    for (int y0 = 0; y0 < g.height(); y0 += kStrip) {
        const int rows = std::min(kStrip, g.height() - y0);
        source.readRows(y0, rows, strip.data());
        // Kept nodata must be exactly source voids: a sample the archive calls data where the
        // source has none would be drawn and exported as an invented height.
        const int finest_width = levels.back().width;
        int64_t invented = 0;
        for (size_t k = 0; k < static_cast<size_t>(rows) * g.width(); ++k) {
            const bool source_void = std::isnan(strip[k]);
            const size_t x = k % g.width(), y = y0 + k / g.width();
            const bool kept = !finest_valid[y * finest_width + x];
            report.source_voids += source_void;
            report.nodata_samples += kept;
            invented += kept && !source_void;
        }
        if (invented)
            problems.add(reader.path() + ": " + std::to_string(invented) +
                         " finest samples are kept as nodata where the source (rows " +
                         std::to_string(y0) + ".." + std::to_string(y0 + rows - 1) +
                         ") has data");
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
                         std::to_string(t.violations) + " source samples deviate more than their patch's Err(P)");
        if (t.level_violations)
            problems.add(reader.path() + ": level " + std::to_string(l) + ": " +
                         std::to_string(t.level_violations) + " level samples deviate more than δ_l");
    }
    report.source_checked = true;
}

} // namespace

VerifyReport verifyArchive(const std::string& archive_path, const VerifyOptions& options)
{
    VerifyReport report;
    ProblemList problems(report.problems);
    try {
        // 1. Header, metadata and index: checksums and every field (the reader refuses a
        // corrupt or inconsistent file, naming the field).
        const ArchiveReader reader(archive_path);
        const PyramidGeometry& g = reader.geometry();

        // 2. Every patch: checksum, decode, min/max, λ, shared borders.
        const double decode_share = options.source ? 0.3 : 1.0;
        std::vector<CodeGrid> levels(g.levelCount());
        std::vector<uint8_t> finest_valid;
        for (int l = 0; l < g.levelCount(); ++l) {
            LevelVerifyReport lr;
            lr.level = l;
            lr.patches = g.patchCount(l);
            const CodeGrid* parents = reader.codec().needsParent(l) ? &levels[l - 1] : nullptr;
            lr.max_err_bound = decodeAndCheckLevel(reader, l, levels[l], parents, problems,
                                                   l == g.finestLevel() ? &finest_valid : nullptr);
            lr.level_bound = reader.levelErrorBound(l);
            report.levels.push_back(lr);
            report.patches_checked += lr.patches;
            reportProgress(options.progress, decode_share * double(l + 1) / g.levelCount());
        }

        // 3. The end-to-end bound against the source, on every valid sample of every level.
        if (options.source)
            compareWithSource(reader, levels, finest_valid, *options.source, report, problems,
                              subProgress(options.progress, decode_share, 1.0));
    } catch (const Cancelled&) {
        throw;
    } catch (const Error& e) {
        problems.add(e.what());
    }
    problems.finish();
    return report;
}

} // namespace ridge
