#include "ridge/codec/progressive_reconstruction.h"

#include "ridge/codec/med_predictor.h"

#include <algorithm>
#include <cstddef>

namespace ridge {

namespace {

// 16 × the interpolated value halfway between line[pos − 1] and line[pos + 1], samples
// `stride` apart along a line of `len` samples. Cubic (Catmull-Rom on a uniform grid:
// −1, 9, 9, −1) where the line allows, quadratic (the 3 nearest: 3, 6, −1 over 8) at its
// ends, linear when the line has only the two samples.
inline int32_t midpoint16(const int32_t* line, ptrdiff_t stride, int pos, int len)
{
    const int32_t a = line[(pos - 1) * stride];
    const int32_t b = line[(pos + 1) * stride];
    const bool has_before = pos - 3 >= 0;
    const bool has_after = pos + 3 < len;
    if (has_before && has_after)
        return 9 * (a + b) - line[(pos - 3) * stride] - line[(pos + 3) * stride];
    if (has_after)
        return 6 * a + 12 * b - 2 * line[(pos + 3) * stride];
    if (has_before)
        return 12 * a + 6 * b - 2 * line[(pos - 3) * stride];
    return 8 * (a + b);
}

// The requantized parent sample under the R sample (x, y) of child `child_index`.
inline int32_t parentBin(const int32_t* parent_q, int child_index, int n, int x, int y)
{
    const int half = (n - 1) / 2;
    const int px = (child_index & 1) * half + x / 2, py = (child_index >> 1) * half + y / 2;
    return parent_q[static_cast<size_t>(py) * n + px];
}

} // namespace

int32_t predictOdd(const int32_t* q, int n, const CodedRegion& region, int x, int y,
                   OddPredictor predictor)
{
    const int w = region.width, h = region.height;
    const int32_t* at = q + static_cast<size_t>(y) * n + x;
    const ptrdiff_t row = n;
    switch (sampleClass(x, y)) {
    case SampleClass::A: // odd x on an even row: between R samples of the row
        if (predictor == OddPredictor::Bilinear)
            return (at[-1] + at[1] + 1) >> 1;
        return (midpoint16(at - x, 1, x, w) + 8) >> 4;
    case SampleClass::B: // odd row, even x: between R samples of the column
        if (predictor == OddPredictor::Bilinear)
            return (at[-row] + at[row] + 1) >> 1;
        return (midpoint16(at - y * row, row, y, h) + 8) >> 4;
    case SampleClass::C: // odd x, odd y
        if (predictor == OddPredictor::Bilinear)
            return (at[-row - 1] + at[-row + 1] + at[row - 1] + at[row + 1] + 2) >> 2;
        // Row through the B samples and column through the A samples, averaged.
        return (midpoint16(at - x, 1, x, w) + midpoint16(at - y * row, row, y, h) + 16) >> 5;
    case SampleClass::R: break;
    }
    return 0; // R samples are refined, not predicted
}

int32_t predictRoot(const int32_t* q, int n, int x, int y)
{
    return medPredictAt(q, n, x, y);
}

// The passes run in the order R, A, B, C; within a pass no sample depends on another, so the
// loops below are what a GPU runs as one dispatch per pass (A and B may even share one).
void childResiduals(const int32_t* q, const int32_t* parent_q, int child_index, int n,
                    const CodedRegion& region, OddPredictor predictor, int32_t* residuals)
{
    if (!region.isWhole(n))
        std::fill(residuals, residuals + static_cast<size_t>(n) * n, 0);
    for (int y = 0; y < region.height; y += 2)
        for (int x = 0; x < region.width; x += 2) {
            const size_t i = static_cast<size_t>(y) * n + x;
            residuals[i] = q[i] - parentBin(parent_q, child_index, n, x, y);
        }
    for (int y = 0; y < region.height; ++y)
        for (int x = (y & 1) ? 0 : 1; x < region.width; x += (y & 1) ? 1 : 2) {
            const size_t i = static_cast<size_t>(y) * n + x;
            residuals[i] = predictOdd(q, n, region, x, y, predictor) - q[i];
        }
}

namespace {

// The cubic A, B, C passes with the line-interior case inlined: what predictOdd computes,
// without its per-sample class switch (the decoder's hot loop; the encoder and the tests
// keep predictOdd, and the round-trip tests hold the two equal).
void cubicPasses(const int32_t* residuals, int n, const CodedRegion& region, int32_t* q)
{
    const int w = region.width, h = region.height;
    const ptrdiff_t s = n;
    for (int y = 0; y < h; y += 2) { // A: along the row through R
        int32_t* row = q + y * s;
        const int32_t* res = residuals + y * s;
        for (int x = 1; x < w; x += 2) {
            const int32_t m = (x >= 3 && x + 3 < w)
                                  ? 9 * (row[x - 1] + row[x + 1]) - row[x - 3] - row[x + 3]
                                  : midpoint16(row, 1, x, w);
            row[x] = ((m + 8) >> 4) - res[x];
        }
    }
    for (int y = 1; y < h; y += 2) { // B: along the column through R
        int32_t* row = q + y * s;
        const int32_t* res = residuals + y * s;
        const bool inner = y >= 3 && y + 3 < h;
        for (int x = 0; x < w; x += 2) {
            const int32_t* at = row + x;
            const int32_t m = inner ? 9 * (at[-s] + at[s]) - at[-3 * s] - at[3 * s]
                                    : midpoint16(at - y * s, s, y, h);
            row[x] = ((m + 8) >> 4) - res[x];
        }
    }
    for (int y = 1; y < h; y += 2) { // C: the row through B and the column through A
        int32_t* row = q + y * s;
        const int32_t* res = residuals + y * s;
        const bool inner = y >= 3 && y + 3 < h;
        for (int x = 1; x < w; x += 2) {
            const int32_t* at = row + x;
            const int32_t mr = (x >= 3 && x + 3 < w)
                                   ? 9 * (at[-1] + at[1]) - at[-3] - at[3]
                                   : midpoint16(row, 1, x, w);
            const int32_t mc = inner ? 9 * (at[-s] + at[s]) - at[-3 * s] - at[3 * s]
                                     : midpoint16(at - y * s, s, y, h);
            row[x] = ((mr + mc + 16) >> 5) - res[x];
        }
    }
}

} // namespace

void reconstructChild(const int32_t* residuals, const int32_t* parent_q, int child_index, int n,
                      const CodedRegion& region, OddPredictor predictor, int32_t* q)
{
    for (int y = 0; y < region.height; y += 2)
        for (int x = 0; x < region.width; x += 2) {
            const size_t i = static_cast<size_t>(y) * n + x;
            q[i] = parentBin(parent_q, child_index, n, x, y) + residuals[i];
        }
    if (predictor == OddPredictor::Cubic) {
        cubicPasses(residuals, n, region, q);
        return;
    }
    for (const SampleClass pass : {SampleClass::A, SampleClass::B, SampleClass::C}) {
        const int x0 = static_cast<int>(pass) & 1, y0 = static_cast<int>(pass) >> 1;
        for (int y = y0; y < region.height; y += 2)
            for (int x = x0; x < region.width; x += 2) {
                const size_t i = static_cast<size_t>(y) * n + x;
                q[i] = predictOdd(q, n, region, x, y, predictor) - residuals[i];
            }
    }
}

void rootResiduals(const int32_t* q, int n, const CodedRegion& region, int32_t* residuals)
{
    if (!region.isWhole(n))
        std::fill(residuals, residuals + static_cast<size_t>(n) * n, 0);
    for (int y = 0; y < region.height; ++y)
        for (int x = 0; x < region.width; ++x) {
            const size_t i = static_cast<size_t>(y) * n + x;
            residuals[i] = predictRoot(q, n, x, y) - q[i];
        }
}

void reconstructRoot(const int32_t* residuals, int n, const CodedRegion& region, int32_t* q)
{
    for (int y = 0; y < region.height; ++y)
        for (int x = 0; x < region.width; ++x) {
            const size_t i = static_cast<size_t>(y) * n + x;
            // Valid bins are <= 65535; the clamp only stops a corrupt stream from letting the
            // raster-order chain overflow int32 on large patches.
            q[i] = std::clamp(predictRoot(q, n, x, y) - residuals[i], -(1 << 24), 1 << 24);
        }
}

void replicateBeyond(int32_t* q, int n, const CodedRegion& region)
{
    if (region.isWhole(n))
        return;
    for (int y = 0; y < region.height; ++y) {
        int32_t* row = q + static_cast<size_t>(y) * n;
        std::fill(row + region.width, row + n, row[region.width - 1]);
    }
    const int32_t* last = q + static_cast<size_t>(region.height - 1) * n;
    for (int y = region.height; y < n; ++y)
        std::copy(last, last + n, q + static_cast<size_t>(y) * n);
}

} // namespace ridge
