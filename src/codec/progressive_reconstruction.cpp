#include "ridge/codec/progressive_reconstruction.h"

#include "ridge/codec/med_predictor.h"
#include "ridge/core/target_clones.h"

#include <algorithm>
#include <cstddef>
#include <optional>
#include <vector>

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

namespace {
int32_t basePrediction(const int32_t* q, int n, const CodedRegion& region, int x, int y,
                       OddPredictor predictor);
} // namespace

int32_t predictionCorrection(const int32_t* q, int n, const CodedRegion& region, int x, int y,
                             int cls, int32_t p0, const PredictorWeights& weights)
{
    const int c = cls - 1;
    if (x < kCorrectionMarginX[c] || x >= region.width - kCorrectionMarginX[c] ||
        y < kCorrectionMarginY[c] || y >= region.height - kCorrectionMarginY[c])
        return 0;
    const int32_t* at = q + static_cast<size_t>(y) * n + x;
    int32_t sum = 0;
    for (int i = 0; i < kCorrectionTapCount; ++i) {
        const CorrectionTap t = kCorrectionTaps[c][i];
        const int32_t d = at[t.dy * static_cast<ptrdiff_t>(n) + t.dx] - p0;
        sum += weights.w[c][i] * std::clamp(d, -32767, 32767);
    }
    return (sum + 2048) >> 12;
}

int32_t predictOdd(const int32_t* q, int n, const CodedRegion& region, int x, int y,
                   OddPredictor predictor, const PredictorWeights* weights)
{
    const int32_t p0 = basePrediction(q, n, region, x, y, predictor);
    if (!weights)
        return p0;
    const int cls = static_cast<int>(sampleClass(x, y));
    return p0 + predictionCorrection(q, n, region, x, y, cls, p0, *weights);
}

namespace {

// P0: the cubic or bilinear prediction, before any correction.
int32_t basePrediction(const int32_t* q, int n, const CodedRegion& region, int x, int y,
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
    case SampleClass::R:
        break;
    }
    return 0; // R samples are refined, not predicted
}

} // namespace

int32_t predictRoot(const int32_t* q, int n, int x, int y)
{
    return medPredictAt(q, n, x, y);
}

// The passes run in the order R, A, B, C; within a pass no sample depends on another, so the
// loops below are what a GPU runs as one dispatch per pass (A and B may even share one).
void childResiduals(const int32_t* q, const int32_t* parent_q, int child_index, int n,
                    const CodedRegion& region, OddPredictor predictor, int32_t* residuals,
                    const PredictorWeights* weights)
{
    if (weights && !weights->any())
        weights = nullptr;
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
            residuals[i] = predictOdd(q, n, region, x, y, predictor, weights) - q[i];
        }
}

namespace {

// The corrections of `count` samples of one row, 2 apart (one class), all inside their
// class's margins: out[k] = (Σ_i w_i · clamp(at[offset_i + 2k] − p0[k], ±32767) + 2048) >> 12,
// predictionCorrection's sum, taps outer and samples inner. GCC keeps the stride-2 loads
// scalar even in the AVX2 clone (which still gains packed min/max); a contiguous variant
// that computes the odd samples too was vectorised but slower (docs/PERF.md).
RIDGE_TARGET_CLONES
void correctRow(const int32_t* __restrict at, const ptrdiff_t* offsets, const int32_t* weights,
                const int32_t* __restrict p0, int count, int32_t* __restrict out)
{
    for (int k = 0; k < count; ++k)
        out[k] = 2048;
    for (int i = 0; i < kCorrectionTapCount; ++i) {
        const int32_t* __restrict t = at + offsets[i];
        const int32_t w = weights[i];
        for (int k = 0; k < count; ++k)
            out[k] += w * std::min(std::max(t[2 * k] - p0[k], -32767), 32767);
    }
    for (int k = 0; k < count; ++k)
        out[k] >>= 12;
}

// One class's taps as offsets for patches of side n, and its interior.
struct Correction {
    ptrdiff_t offset[kCorrectionTapCount];
    int32_t weight[kCorrectionTapCount];
    int x0, x1, y0, y1; // the interior: [x0, x1) × [y0, y1)

    Correction(const PredictorWeights& w, int c, int n, const CodedRegion& r)
        : x0(kCorrectionMarginX[c]), x1(r.width - kCorrectionMarginX[c]), y0(kCorrectionMarginY[c]),
          y1(r.height - kCorrectionMarginY[c])
    {
        for (int i = 0; i < kCorrectionTapCount; ++i) {
            offset[i] =
                kCorrectionTaps[c][i].dy * static_cast<ptrdiff_t>(n) + kCorrectionTaps[c][i].dx;
            weight[i] = w.w[c][i];
        }
    }
    bool rowInside(int y) const { return y >= y0 && y < y1; }

    // Row y's predictions p0[k] of samples x = first + 2k (k < count) plus their corrections,
    // in place.
    void apply(const int32_t* row, int first, int count, int32_t* p0) const
    {
        thread_local std::vector<int32_t> corr;
        // Interior samples: x in [x0, x1) with x's parity.
        int k0 = 0;
        while (k0 < count && first + 2 * k0 < x0)
            ++k0;
        int k1 = k0;
        while (k1 < count && first + 2 * k1 < x1)
            ++k1;
        if (k1 <= k0)
            return;
        corr.resize(size_t(k1 - k0));
        correctRow(row + first + 2 * k0, offset, weight, p0 + k0, k1 - k0, corr.data());
        for (int k = k0; k < k1; ++k)
            p0[k] += corr[size_t(k - k0)];
    }
};

// The cubic A, B, C passes with the line-interior case inlined: what predictOdd computes,
// without its per-sample class switch (the decoder's hot loop; the encoder and the tests
// keep predictOdd, and the round-trip tests hold the two equal). `weights`: the
// least-squares corrections, or null.
void cubicPasses(const int32_t* residuals, int n, const CodedRegion& region, int32_t* q,
                 const PredictorWeights* weights)
{
    const int w = region.width, h = region.height;
    const ptrdiff_t s = n;
    // Each row: P0 of its samples into p, the corrections where the class has them, then the
    // samples. The three classes differ only in P0 and in where their samples start.
    thread_local std::vector<int32_t> p;
    p.resize(size_t(n));
    auto finishRow = [&](int y, int first, const Correction* correction) {
        int32_t* row = q + y * s;
        const int32_t* res = residuals + y * s;
        const int count = (w - first + 1) / 2;
        if (correction && correction->rowInside(y))
            correction->apply(row, first, count, p.data());
        for (int k = 0, x = first; k < count; ++k, x += 2)
            row[x] = p[k] - res[x];
    };
    std::optional<Correction> ca, cb, cc;
    if (weights) {
        ca.emplace(*weights, 0, n, region);
        cb.emplace(*weights, 1, n, region);
        cc.emplace(*weights, 2, n, region);
    }
    for (int y = 0; y < h; y += 2) { // A: along the row through R
        const int32_t* row = q + y * s;
        for (int x = 1, k = 0; x < w; x += 2, ++k) {
            const int32_t m = (x >= 3 && x + 3 < w)
                                  ? 9 * (row[x - 1] + row[x + 1]) - row[x - 3] - row[x + 3]
                                  : midpoint16(row, 1, x, w);
            p[k] = (m + 8) >> 4;
        }
        finishRow(y, 1, ca ? &*ca : nullptr);
    }
    for (int y = 1; y < h; y += 2) { // B: along the column through R
        const int32_t* row = q + y * s;
        const bool inner = y >= 3 && y + 3 < h;
        for (int x = 0, k = 0; x < w; x += 2, ++k) {
            const int32_t* at = row + x;
            const int32_t m = inner ? 9 * (at[-s] + at[s]) - at[-3 * s] - at[3 * s]
                                    : midpoint16(at - y * s, s, y, h);
            p[k] = (m + 8) >> 4;
        }
        finishRow(y, 0, cb ? &*cb : nullptr);
    }
    for (int y = 1; y < h; y += 2) { // C: the row through B and the column through A
        const int32_t* row = q + y * s;
        const bool inner = y >= 3 && y + 3 < h;
        for (int x = 1, k = 0; x < w; x += 2, ++k) {
            const int32_t* at = row + x;
            const int32_t mr = (x >= 3 && x + 3 < w) ? 9 * (at[-1] + at[1]) - at[-3] - at[3]
                                                     : midpoint16(row, 1, x, w);
            const int32_t mc = inner ? 9 * (at[-s] + at[s]) - at[-3 * s] - at[3 * s]
                                     : midpoint16(at - y * s, s, y, h);
            p[k] = (mr + mc + 16) >> 5;
        }
        finishRow(y, 1, cc ? &*cc : nullptr);
    }
}

} // namespace

void reconstructChild(const int32_t* residuals, const int32_t* parent_q, int child_index, int n,
                      const CodedRegion& region, OddPredictor predictor, int32_t* q,
                      const PredictorWeights* weights)
{
    if (weights && !weights->any())
        weights = nullptr;
    for (int y = 0; y < region.height; y += 2)
        for (int x = 0; x < region.width; x += 2) {
            const size_t i = static_cast<size_t>(y) * n + x;
            q[i] = parentBin(parent_q, child_index, n, x, y) + residuals[i];
        }
    if (predictor == OddPredictor::Cubic) {
        cubicPasses(residuals, n, region, q, weights);
        return;
    }
    for (const SampleClass pass : {SampleClass::A, SampleClass::B, SampleClass::C}) {
        const int x0 = static_cast<int>(pass) & 1, y0 = static_cast<int>(pass) >> 1;
        for (int y = y0; y < region.height; y += 2)
            for (int x = x0; x < region.width; x += 2) {
                const size_t i = static_cast<size_t>(y) * n + x;
                q[i] = predictOdd(q, n, region, x, y, predictor, weights) - residuals[i];
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
