// What each level of an archive must be given the next one, checked on the decoded levels
// without the source (docs/FORMAT.md, "Error bounds" and "Validity mask"): stored Err_Appr
// not below the interpolation error the levels show, and every validity mask the one the
// finest level's sample validity determines.
#include "verify_internal.h"

#include "ridge/pyramid/level_pyramid.h"
#include "ridge/pyramid/patch_error.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace ridge::verify_detail {

namespace {

using archive::ArchiveReader;

// The decoded level as the build's LevelView sees a pyramid level: `width` × `height`
// samples cover the valid extent, the grid beyond them is patch padding.
LevelView viewOf(const PyramidGeometry& g, int level, const CodeGrid& grid)
{
    LevelView v;
    v.source = grid.codes.data();
    v.src_width = grid.width;
    v.src_height = grid.height;
    v.step = 1;
    v.width = g.levelWidth(level);
    v.height = g.levelHeight(level);
    return v;
}

// Whether every existing patch of `level` in [x0, x1] × [y0, y1] decoded.
bool allDecoded(const PyramidGeometry& g, const DecodedLevel& decoded, int level, int x0, int y0,
                int x1, int y1)
{
    for (int y = y0; y <= std::min(y1, g.patchesY(level) - 1); ++y)
        for (int x = x0; x <= std::min(x1, g.patchesX(level) - 1); ++x)
            if (!decoded.patchDecoded(g, level, x, y))
                return false;
    return true;
}

std::string metres(double v)
{
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g m", v);
    return buf;
}

// "2 of 1089 samples valid, 0 of 1024 cells drawable" for a mask.
std::string describeMask(const PatchValidity& v)
{
    const int n = v.patch_size, c = n - 1;
    int64_t samples = 0, cells = 0;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i)
            samples += v.sampleValid(i, j);
    for (int j = 0; j < c; ++j)
        for (int i = 0; i < c; ++i)
            cells += v.cellDrawable(i, j);
    return std::to_string(samples) + " of " + std::to_string(int64_t{n} * n) + " samples valid, " +
           std::to_string(cells) + " of " + std::to_string(int64_t{c} * c) + " cells drawable";
}

bool sameMask(const PatchValidity& a, const PatchValidity& b)
{
    if (a.kind != b.kind)
        return false;
    return a.kind != PatchValidity::Kind::Mixed || (a.samples == b.samples && a.cells == b.cells);
}

} // namespace

void checkErrorBounds(const ArchiveReader& reader, const std::vector<DecodedLevel>& levels,
                      ProblemList& problems)
{
    const PyramidGeometry& g = reader.geometry();
    const int n = g.patchSize(), cells = g.cells();
    const double scale = reader.header().height_scale;
    for (int l = 0; l < g.finestLevel(); ++l) {
        const DecodedLevel& parent = levels[l];
        const DecodedLevel& child = levels[l + 1];
        const LevelView child_view = viewOf(g, l + 1, child.grid);
        // Codes by which the decoded levels may differ from the coded ones (0 when lossless).
        const double slack_codes =
            reader.codec().levelErrorBound(l) + reader.codec().levelErrorBound(l + 1);
        const int nx = g.patchesX(l), ny = g.patchesY(l);
#pragma omp parallel for schedule(dynamic, 1)
        for (int64_t k = 0; k < int64_t{nx} * ny; ++k) {
            const PatchId p{l, static_cast<int>(k % nx), static_cast<int>(k / nx)};
            // The grids hold each patch's own samples; the last row and column of a patch
            // are its east and south neighbours' own. A patch that did not decode left
            // zeros there, and its failure is reported: nothing is measured on them.
            if (!allDecoded(g, parent, l, p.x, p.y, p.x + 1, p.y + 1) ||
                !allDecoded(g, child, l + 1, 2 * p.x, 2 * p.y, 2 * p.x + 2, 2 * p.y + 2))
                continue;
            float worst_child = 0.f;
            for (int c = 0; c < 4; ++c) {
                const PatchId q{l + 1, 2 * p.x + (c & 1), 2 * p.y + (c >> 1)};
                if (g.exists(q))
                    worst_child = std::max(worst_child, reader.record(q).err_appr);
            }
            std::vector<uint16_t> samples(static_cast<size_t>(n) * n);
            for (int j = 0; j < n; ++j)
                std::copy_n(
                    &parent.grid.codes[static_cast<size_t>(p.y * cells + j) * parent.grid.width +
                                       static_cast<size_t>(p.x) * cells],
                    n, samples.data() + static_cast<size_t>(j) * n);
            const double err_int_codes = interpolationError(samples.data(), child_view, n, p);
            const double err_int = std::max(0.0, err_int_codes - slack_codes) * scale;
            const double required = err_int + double(worst_child);
            const float stored = reader.record(p).err_appr;
            // The writer rounds each Err_Appr up to f32 from the exact sum, the children's
            // included, so a relative f32 rounding is all the slack there is.
            if (double(stored) < required * (1.0 - 1e-6) - 1e-9 * scale)
                problems.add(reader.describe(p) + ": stored Err_Appr " + metres(stored) +
                             " is below Err_Int " + metres(err_int) +
                             " (measured on the decoded levels" +
                             (slack_codes > 0 ? ", less the codec bounds" : "") +
                             ") + its children's largest Err_Appr " + metres(worst_child) +
                             ": the error bound is understated");
        }
    }
}

namespace {

// Calls fn(patch, its level, its index in the level) for every patch whose masks were read.
template <typename Fn>
void forEachReadPatch(const PyramidGeometry& g, const std::vector<DecodedLevel>& levels, Fn fn)
{
    for (int l = 0; l < g.levelCount(); ++l) {
        const int nx = g.patchesX(l), ny = g.patchesY(l);
        for (int64_t k = 0; k < int64_t{nx} * ny; ++k)
            if (levels[l].mask_read[k])
                fn(PatchId{l, static_cast<int>(k % nx), static_cast<int>(k / nx)}, levels[l],
                   static_cast<size_t>(k));
    }
}

} // namespace

void checkValidityPyramid(const ArchiveReader& reader, const std::vector<DecodedLevel>& levels,
                          const std::vector<uint8_t>& finest_valid, ProblemList& problems)
{
    const PyramidGeometry& g = reader.geometry();
    std::vector<uint8_t> nodata(finest_valid.size());
    for (size_t i = 0; i < nodata.size(); ++i)
        nodata[i] = finest_valid[i] ? 0 : 1;
    const ValidityPyramid derived(nodata, g, reader.filter());
    forEachReadPatch(g, levels, [&](PatchId p, const DecodedLevel& level, size_t k) {
        const PatchValidity expected = derived.patch(p);
        const PatchValidity& stored = level.validity[k];
        if (!sameMask(stored, expected))
            problems.add(reader.describe(p) + ": validity mask (" + describeMask(stored) +
                         ") differs from the one the finest level's sample validity "
                         "determines (" +
                         describeMask(expected) + "; docs/FORMAT.md, \"Validity mask\")");
    });
}

namespace {

std::string describeFlags(const PatchSampleFlags& f)
{
    switch (f.kind) {
    case PatchSampleFlags::Kind::None:
        return "no flag";
    case PatchSampleFlags::Kind::AllWater:
        return "all water";
    case PatchSampleFlags::Kind::Mixed:
        break;
    }
    size_t water = 0, filled = 0;
    for (uint8_t b : f.flags) {
        water += (b & kSampleWater) != 0;
        filled += (b & kSampleFilled) != 0;
    }
    return std::to_string(water) + " water and " + std::to_string(filled) + " filled samples";
}

} // namespace

void checkSampleFlagsPyramid(const ArchiveReader& reader, const std::vector<DecodedLevel>& levels,
                             const std::vector<uint8_t>& finest_flags, ProblemList& problems)
{
    const PyramidGeometry& g = reader.geometry();
    const SampleFlagsPyramid derived(SampleFlagsGrid(finest_flags, g.width(), g.height()),
                                     g.finestLevel(), g);
    forEachReadPatch(g, levels, [&](PatchId p, const DecodedLevel& level, size_t k) {
        const PatchSampleFlags expected = derived.patch(p);
        const PatchSampleFlags& stored = level.flags[k];
        if (stored.kind != expected.kind || stored.flags != expected.flags)
            problems.add(reader.describe(p) + ": sample flags (" + describeFlags(stored) +
                         ") differ from those the finest level's flags determine (" +
                         describeFlags(expected) + "; docs/FORMAT.md, \"Sample flags\")");
    });
    const int64_t water = std::count_if(finest_flags.begin(), finest_flags.end(),
                                        [](uint8_t f) { return (f & kSampleWater) != 0; });
    if (water != reader.metadata().water.samples)
        problems.add(reader.path() + ": metadata: water.samples is " +
                     std::to_string(reader.metadata().water.samples) +
                     " but the finest level has " + std::to_string(water) + " water samples");
}

} // namespace ridge::verify_detail
