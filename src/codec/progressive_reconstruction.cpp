#include "ridge/codec/progressive_reconstruction.h"

#include "ridge/codec/med_predictor.h"
#include "ridge/core/target_clones.h"

#include <algorithm>
#include <cstddef>
#include <optional>
#include <vector>

namespace ridge {

namespace {

// 16 × the midpoint between line[i] and line[i + 1] of a line of `count` known samples,
// `stride` apart: cubic (Catmull-Rom on a uniform grid: −1, 9, 9, −1) where the line allows,
// quadratic (the 3 nearest: 3, 6, −1 over 8) at its ends, linear when the line has only the
// two samples.
inline int32_t planeMidpoint16(const int32_t* line, ptrdiff_t stride, int i, int count)
{
    const int32_t a = line[i * stride];
    const int32_t b = line[(i + 1) * stride];
    const bool has_before = i >= 1;
    const bool has_after = i + 2 < count;
    if (has_before && has_after)
        return 9 * (a + b) - line[(i - 1) * stride] - line[(i + 2) * stride];
    if (has_after)
        return 6 * a + 12 * b - 2 * line[(i + 2) * stride];
    if (has_before)
        return 12 * a + 6 * b - 2 * line[(i - 1) * stride];
    return 8 * (a + b);
}

// The same halfway between line[pos − 1] and line[pos + 1] of an interleaved line of `len`
// samples (odd, as every coded region's sides are), whose known samples are the even ones.
inline int32_t midpoint16(const int32_t* line, ptrdiff_t stride, int pos, int len)
{
    return planeMidpoint16(line, 2 * stride, (pos - 1) / 2, (len + 1) / 2);
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

// The decoder's cubic passes on planes: R (even x, even y), A (odd x, even y), B (even x,
// odd y) and C (odd x, odd y), each row-major with its own width. In a plane every cubic tap
// and every correction tap of a pass is a whole row of an earlier plane, read at unit
// stride, so the prediction and correction loops vectorise (on the interleaved grid they read
// every other sample). The arithmetic is predictOdd's, term for term: the encoder keeps
// predictOdd, and the round-trip tests hold the two equal. The planes are interleaved back
// into q at the end.
struct Planes {
    int rw, rh, aw, bh; // R: rw × rh; A: aw × rh; B: rw × bh; C: aw × bh
    std::vector<int32_t> r, a, b, c;

    Planes(int w, int h) : rw((w + 1) / 2), rh((h + 1) / 2), aw((w - 1) / 2), bh((h - 1) / 2)
    {
        r.resize(size_t(rw) * rh);
        a.resize(size_t(aw) * rh);
        b.resize(size_t(rw) * bh);
        c.resize(size_t(aw) * bh);
    }
    int32_t* R(int j) { return r.data() + size_t(j) * rw; }
    int32_t* A(int j) { return a.data() + size_t(j) * aw; }
    int32_t* B(int j) { return b.data() + size_t(j) * rw; }
    int32_t* C(int j) { return c.data() + size_t(j) * aw; }
};

// m[i] = planeMidpoint16(line, 1, i, count) for i in [0, count − 1): the ends apart, so the
// interior loop vectorises.
void lineMidpoints(const int32_t* __restrict line, int count, int32_t* __restrict m)
{
    const int last = count - 2; // the last midpoint
    m[0] = planeMidpoint16(line, 1, 0, count);
    for (int i = 1; i < last; ++i)
        m[i] = 9 * (line[i] + line[i + 1]) - line[i - 1] - line[i + 2];
    if (last > 0)
        m[last] = planeMidpoint16(line, 1, last, count);
}

// p[k] += (Σ_t w_t · clamp(tap_t[k] − p[k], ±32767) + 2048) >> 12 for k in [0, count):
// predictionCorrection's sum, taps outer and samples inner, every tap a unit-stride row.
RIDGE_TARGET_CLONES
void correctPlaneRow(const int32_t* const* taps, const int32_t* weights, int count,
                     int32_t* __restrict p)
{
    thread_local std::vector<int32_t> sum;
    sum.resize(size_t(count));
    int32_t* __restrict acc = sum.data();
    for (int k = 0; k < count; ++k)
        acc[k] = 2048;
    for (int t = 0; t < kCorrectionTapCount; ++t) {
        const int32_t* __restrict tap = taps[t];
        const int32_t w = weights[t];
        for (int k = 0; k < count; ++k)
            acc[k] += w * std::min(std::max(tap[k] - p[k], -32767), 32767);
    }
    for (int k = 0; k < count; ++k)
        p[k] += acc[k] >> 12;
}

// The 12 tap rows of a correction, in kCorrectionTaps order, each offset so that taps[t][k]
// is tap t of the pass's sample k + 1 (every interior starts at sample 1; no pointer before
// a plane's first sample is formed).
struct TapRows {
    const int32_t* row[kCorrectionTapCount];
};

void weightsOf(const PredictorWeights& w, int c, int32_t* out)
{
    for (int t = 0; t < kCorrectionTapCount; ++t)
        out[t] = w.w[c][t];
}

// Row j of A (samples x = 2i + 1, y = 2j) from R: cubic along the row, then the correction
// where all its taps lie inside (i in [1, rw − 2), j in [1, rh − 1)), then the residuals.
void planeRowA(Planes& pl, int j, const int32_t* res_row, const int32_t* weights)
{
    const int32_t* r = pl.R(j);
    int32_t* p = pl.A(j);
    lineMidpoints(r, pl.rw, p);
    for (int i = 0; i < pl.aw; ++i)
        p[i] = (p[i] + 8) >> 4;
    if (weights && j >= 1 && j + 1 < pl.rh && pl.rw > 3) {
        const int32_t *up = pl.R(j - 1), *down = pl.R(j + 1);
        const TapRows t{{r + 1, r + 2, r, r + 3, up + 1, up + 2, down + 1, down + 2, up, up + 3,
                         down, down + 3}};
        correctPlaneRow(t.row, weights, pl.rw - 3, p + 1);
    }
    for (int i = 0; i < pl.aw; ++i)
        p[i] -= res_row[2 * i + 1];
}

// Row j of B (x = 2i, y = 2j + 1) from R and A: cubic along the column, the correction for
// i in [1, rw − 1), j in [1, rh − 2).
void planeRowB(Planes& pl, int j, const int32_t* res_row, const int32_t* weights)
{
    int32_t* p = pl.B(j);
    const int32_t *r0 = pl.R(j), *r1 = pl.R(j + 1);
    if (j >= 1 && j + 2 < pl.rh) {
        const int32_t *rm = pl.R(j - 1), *r2 = pl.R(j + 2);
        for (int i = 0; i < pl.rw; ++i)
            p[i] = (9 * (r0[i] + r1[i]) - rm[i] - r2[i] + 8) >> 4;
    } else {
        for (int i = 0; i < pl.rw; ++i)
            p[i] = (planeMidpoint16(pl.r.data() + i, pl.rw, j, pl.rh) + 8) >> 4;
    }
    if (weights && j >= 1 && j + 2 < pl.rh && pl.rw > 2) {
        const int32_t *rm = pl.R(j - 1), *r2 = pl.R(j + 2), *a0 = pl.A(j), *a1 = pl.A(j + 1);
        const TapRows t{
            {r0 + 1, r1 + 1, rm + 1, r2 + 1, r0, r0 + 2, r1, r1 + 2, a0, a0 + 1, a1, a1 + 1}};
        correctPlaneRow(t.row, weights, pl.rw - 2, p + 1);
    }
    for (int i = 0; i < pl.rw; ++i)
        p[i] -= res_row[2 * i];
}

// Row j of C (x = 2i + 1, y = 2j + 1): the row cubic through B and the column cubic through A,
// averaged; the correction for i in [1, rw − 2), j in [1, rh − 2).
void planeRowC(Planes& pl, int j, const int32_t* res_row, const int32_t* weights)
{
    int32_t* p = pl.C(j);
    const int32_t* b = pl.B(j);
    const int32_t *a0 = pl.A(j), *a1 = pl.A(j + 1);
    const bool inner = j >= 1 && j + 2 < pl.rh;
    lineMidpoints(b, pl.rw, p); // the row through B
    if (inner) {
        const int32_t *am = pl.A(j - 1), *a2 = pl.A(j + 2);
        for (int i = 0; i < pl.aw; ++i)
            p[i] = (p[i] + 9 * (a0[i] + a1[i]) - am[i] - a2[i] + 16) >> 5;
    } else {
        for (int i = 0; i < pl.aw; ++i)
            p[i] = (p[i] + planeMidpoint16(pl.a.data() + i, pl.aw, j, pl.rh) + 16) >> 5;
    }
    if (weights && inner && pl.rw > 3) {
        const int32_t *r0 = pl.R(j), *r1 = pl.R(j + 1), *am = pl.A(j - 1), *a2 = pl.A(j + 2);
        const TapRows t{{a0 + 1, a1 + 1, b + 1, b + 2, r0 + 1, r0 + 2, r1 + 1, r1 + 2, am + 1,
                         a2 + 1, b, b + 3}};
        correctPlaneRow(t.row, weights, pl.rw - 3, p + 1);
    }
    for (int i = 0; i < pl.aw; ++i)
        p[i] -= res_row[2 * i + 1];
}

// The cubic A, B, C passes on planes (see Planes), R from the parent and the refinements.
void cubicPasses(const int32_t* residuals, const int32_t* parent_q, int child_index, int n,
                 const CodedRegion& region, int32_t* q, const PredictorWeights* weights)
{
    thread_local std::optional<Planes> storage;
    if (!storage || storage->rw != (region.width + 1) / 2 || storage->rh != (region.height + 1) / 2)
        storage.emplace(region.width, region.height);
    Planes& pl = *storage;
    const int half = (n - 1) / 2;
    const int32_t* parent =
        parent_q + size_t((child_index >> 1) * half) * n + (child_index & 1) * half;
    for (int j = 0; j < pl.rh; ++j) {
        const int32_t* res = residuals + size_t(2 * j) * n;
        const int32_t* base = parent + size_t(j) * n;
        int32_t* r = pl.R(j);
        for (int i = 0; i < pl.rw; ++i)
            r[i] = base[i] + res[2 * i];
    }
    int32_t wa[kCorrectionTapCount], wb[kCorrectionTapCount], wc[kCorrectionTapCount];
    if (weights) {
        weightsOf(*weights, 0, wa);
        weightsOf(*weights, 1, wb);
        weightsOf(*weights, 2, wc);
    }
    for (int j = 0; j < pl.rh; ++j)
        planeRowA(pl, j, residuals + size_t(2 * j) * n, weights ? wa : nullptr);
    for (int j = 0; j < pl.bh; ++j)
        planeRowB(pl, j, residuals + size_t(2 * j + 1) * n, weights ? wb : nullptr);
    for (int j = 0; j < pl.bh; ++j)
        planeRowC(pl, j, residuals + size_t(2 * j + 1) * n, weights ? wc : nullptr);
    // Interleave: even rows R A R A ... R, odd rows B C B C ... B.
    for (int j = 0; j < pl.rh; ++j) {
        int32_t* even = q + size_t(2 * j) * n;
        const int32_t *r = pl.R(j), *a = pl.A(j);
        for (int i = 0; i < pl.aw; ++i) {
            even[2 * i] = r[i];
            even[2 * i + 1] = a[i];
        }
        even[2 * pl.aw] = r[pl.aw];
        if (j == pl.bh)
            break;
        int32_t* odd = even + n;
        const int32_t *b = pl.B(j), *c = pl.C(j);
        for (int i = 0; i < pl.aw; ++i) {
            odd[2 * i] = b[i];
            odd[2 * i + 1] = c[i];
        }
        odd[2 * pl.aw] = b[pl.aw];
    }
}

} // namespace

void reconstructChild(const int32_t* residuals, const int32_t* parent_q, int child_index, int n,
                      const CodedRegion& region, OddPredictor predictor, int32_t* q,
                      const PredictorWeights* weights)
{
    if (weights && !weights->any())
        weights = nullptr;
    if (predictor == OddPredictor::Cubic) {
        cubicPasses(residuals, parent_q, child_index, n, region, q, weights);
        return;
    }
    for (int y = 0; y < region.height; y += 2)
        for (int x = 0; x < region.width; x += 2) {
            const size_t i = static_cast<size_t>(y) * n + x;
            q[i] = parentBin(parent_q, child_index, n, x, y) + residuals[i];
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
