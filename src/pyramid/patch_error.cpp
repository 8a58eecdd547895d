#include "ridge/pyramid/patch_error.h"

#include "ridge/core/target_clones.h"

#include <algorithm>
#include <cmath>

namespace ridge {

namespace {

// Worst deviation (times 4, in codes) of child samples on an even child row (coinciding with
// parent row `p`): even columns coincide with parent samples, odd ones lie mid-edge.
RIDGE_TARGET_CLONES
int evenRowDeviationX4(const uint16_t* c, const uint16_t* p, int count)
{
    int worst = 0;
    for (int i = 0; i < count; ++i) {
        const int pa = p[i >> 1], pb = p[(i + 1) >> 1];
        // Even i: pa == pb, so 2*|2c - (pa+pb)| = 4*|c - pa|.
        worst = std::max(worst, 2 * std::abs(2 * c[i] - (pa + pb)));
    }
    return worst;
}

// Same for an odd child row between parent rows `p0` and `p1`: even columns lie mid-edge,
// odd ones at parent cell centres, where the bilinear value and both diagonals are checked.
RIDGE_TARGET_CLONES
int oddRowDeviationX4(const uint16_t* c, const uint16_t* p0, const uint16_t* p1, int count)
{
    int worst = 0;
    for (int i = 0; i < count; ++i) {
        const int a = p0[i >> 1], b = p0[(i + 1) >> 1];
        const int d = p1[i >> 1], e = p1[(i + 1) >> 1];
        const int c4 = 4 * c[i];
        // Even i: a == b and d == e, so every term is 4*|c - (a+d)/2|.
        const int bilinear = std::abs(c4 - (a + b + d + e));
        const int diag_ae = std::abs(c4 - 2 * (a + e));
        const int diag_bd = std::abs(c4 - 2 * (b + d));
        worst = std::max(worst, std::max(bilinear, std::max(diag_ae, diag_bd)));
    }
    return worst;
}

} // namespace

double interpolationError(const LevelView& parent, const LevelView& child, int patch_size,
                          PatchId p)
{
    thread_local std::vector<uint16_t> parent_samples;
    parent_samples.resize(static_cast<size_t>(patch_size) * patch_size);
    extractPatch(parent, patch_size, p, parent_samples.data());
    return interpolationError(parent_samples.data(), child, patch_size, p);
}

double interpolationError(const uint16_t* parent_samples, const LevelView& child, int patch_size,
                          PatchId p)
{
    const int n = patch_size;
    const int64_t cells = n - 1;
    const int m = 2 * static_cast<int>(cells) + 1; // the four children's joined samples
    thread_local std::vector<uint16_t> child_samples;
    child_samples.resize(static_cast<size_t>(m) * m);
    const int64_t i0 = 2 * p.x * cells, j0 = 2 * p.y * cells;
    extractWindow(child, i0, j0, m, m, child_samples.data());

    // Only child samples whose cells touch the valid extent count.
    const int count_x = static_cast<int>(std::min<int64_t>(m, child.width - i0));
    const int count_y = static_cast<int>(std::min<int64_t>(m, child.height - j0));
    int worst_x4 = 0;
    for (int j = 0; j < count_y; ++j) {
        const uint16_t* c = child_samples.data() + static_cast<size_t>(j) * m;
        const uint16_t* p0 = parent_samples + static_cast<size_t>(j >> 1) * n;
        worst_x4 = std::max(worst_x4, (j & 1) ? oddRowDeviationX4(c, p0, p0 + n, count_x)
                                              : evenRowDeviationX4(c, p0, count_x));
    }
    return worst_x4 / 4.0;
}

PatchErrors makePatchErrors(const PyramidGeometry& geometry)
{
    PatchErrors errors;
    errors.err_int.assign(geometry.patchCount(), 0.f);
    errors.err_appr.assign(geometry.patchCount(), 0.f);
    errors.min_code.assign(geometry.patchCount(), 0);
    errors.max_code.assign(geometry.patchCount(), 0);
    return errors;
}

void measurePatches(const LevelPyramid& pyramid, int first_level, int last_level,
                    PatchErrors& errors)
{
    const PyramidGeometry& g = pyramid.geometry();
    const int64_t begin = g.firstPatchIndex(first_level);
    const int64_t end = g.firstPatchIndex(last_level) + g.patchCount(last_level);
#pragma omp parallel
    {
        std::vector<uint16_t> samples(static_cast<size_t>(g.patchSize()) * g.patchSize());
#pragma omp for schedule(dynamic, 4)
        for (int64_t index = begin; index < end; ++index) {
            const PatchId p = g.patchAt(index);
            extractPatch(pyramid.level(p.level), g.patchSize(), p, samples.data());
            const auto [lo, hi] = std::minmax_element(samples.begin(), samples.end());
            errors.min_code[index] = *lo;
            errors.max_code[index] = *hi;
            if (p.level < g.finestLevel())
                errors.err_int[index] = static_cast<float>(interpolationError(
                    samples.data(), pyramid.level(p.level + 1), g.patchSize(), p));
        }
    }
}

void accumulatePatchErrors(const PyramidGeometry& g, int final_level, PatchErrors& errors)
{
    // Values are exact multiples of 1/4 code, so float sums stay exact for any realistic
    // height range.
    for (int l = final_level - 1; l >= 0; --l) {
        for (int y = 0; y < g.patchesY(l); ++y) {
            for (int x = 0; x < g.patchesX(l); ++x) {
                const int64_t index = g.patchIndex({l, x, y});
                float worst_child = 0.f;
                for (int c = 0; c < 4; ++c) {
                    const PatchId child{l + 1, 2 * x + (c & 1), 2 * y + (c >> 1)};
                    if (!g.exists(child))
                        continue;
                    const int64_t ci = g.patchIndex(child);
                    worst_child = std::max(worst_child, errors.err_appr[ci]);
                    errors.min_code[index] = std::min(errors.min_code[index], errors.min_code[ci]);
                    errors.max_code[index] = std::max(errors.max_code[index], errors.max_code[ci]);
                }
                errors.err_appr[index] = errors.err_int[index] + worst_child;
            }
        }
    }
}

PatchErrors computePatchErrors(const LevelPyramid& pyramid)
{
    const PyramidGeometry& g = pyramid.geometry();
    PatchErrors errors = makePatchErrors(g);
    measurePatches(pyramid, 0, g.finestLevel(), errors);
    accumulatePatchErrors(g, g.finestLevel(), errors);
    return errors;
}

} // namespace ridge
