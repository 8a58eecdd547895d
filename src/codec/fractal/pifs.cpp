#include "pifs.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ridge::fractal {

Partition Partition::of(int n)
{
    Partition p;
    p.n = n;
    p.ranges_per_side = (n + kRangeSide - 1) / kRangeSide;
    p.side = p.ranges_per_side * kRangeSide;
    p.domains_per_side = p.ranges_per_side - 1;
    return p;
}

namespace {

// The padded image of the patch, side m: samples beyond n repeat the last row and column.
std::vector<double> paddedImage(const uint16_t* codes, const Partition& p)
{
    std::vector<double> image(size_t(p.side) * p.side);
    for (int y = 0; y < p.side; ++y)
        for (int x = 0; x < p.side; ++x)
            image[size_t(y) * p.side + x] =
                codes[size_t(std::min(y, p.n - 1)) * p.n + std::min(x, p.n - 1)];
    return image;
}

// A domain block shrunk by averaging 2 × 2 to range size, and its sums for least squares.
struct Shrunk {
    double d[kRangeSide * kRangeSide];
    double sum = 0.0, sum_sq = 0.0;
};

std::vector<Shrunk> shrunkDomains(const std::vector<double>& image, const Partition& p)
{
    std::vector<Shrunk> domains(size_t(p.domains_per_side) * p.domains_per_side);
    for (int by = 0; by < p.domains_per_side; ++by)
        for (int bx = 0; bx < p.domains_per_side; ++bx) {
            Shrunk& s = domains[size_t(by) * p.domains_per_side + bx];
            for (int v = 0; v < kRangeSide; ++v)
                for (int u = 0; u < kRangeSide; ++u) {
                    const int x = bx * kRangeSide + 2 * u, y = by * kRangeSide + 2 * v;
                    const double* row = &image[size_t(y) * p.side + x];
                    const double mean = 0.25 * (row[0] + row[1] + row[p.side] + row[p.side + 1]);
                    s.d[v * kRangeSide + u] = mean;
                    s.sum += mean;
                    s.sum_sq += mean * mean;
                }
        }
    return domains;
}

// The least-squares s and o of R ≈ s·D + o (the paper's formulas), quantized as stored, and
// the squared error of the quantized transform.
Transform fit(const double* r, double r_sum, const Shrunk& d, double& error)
{
    constexpr double n = kRangeSide * kRangeSide;
    double dr = 0.0;
    for (int i = 0; i < kRangeSide * kRangeSide; ++i)
        dr += d.d[i] * r[i];
    const double denominator = n * d.sum_sq - d.sum * d.sum;
    const double s = denominator > 1e-9 ? (n * dr - d.sum * r_sum) / denominator : 0.0;
    Transform t;
    t.s =
        int32_t(std::clamp(std::lround(s * kScaleDenominator), long(-kMaxScale), long(kMaxScale)));
    const double sq = double(t.s) / kScaleDenominator;
    t.o = int32_t(
        std::clamp(std::lround((r_sum - sq * d.sum) / n), long(-kMaxOffset), long(kMaxOffset)));
    error = 0.0;
    for (int i = 0; i < kRangeSide * kRangeSide; ++i) {
        const double e = sq * d.d[i] + t.o - r[i];
        error += e * e;
    }
    return t;
}

} // namespace

std::vector<Transform> encodeTransforms(const uint16_t* codes, const Partition& p, int search)
{
    const std::vector<double> image = paddedImage(codes, p);
    const std::vector<Shrunk> domains = shrunkDomains(image, p);
    std::vector<Transform> transforms(size_t(p.rangeCount()));
    const int reach = search > 0 ? search : p.domains_per_side;
    for (int ry = 0; ry < p.ranges_per_side; ++ry)
        for (int rx = 0; rx < p.ranges_per_side; ++rx) {
            double r[kRangeSide * kRangeSide], r_sum = 0.0;
            for (int v = 0; v < kRangeSide; ++v)
                for (int u = 0; u < kRangeSide; ++u) {
                    r[v * kRangeSide + u] =
                        image[size_t(ry * kRangeSide + v) * p.side + rx * kRangeSide + u];
                    r_sum += r[v * kRangeSide + u];
                }
            const int cx = std::min(rx, p.domains_per_side - 1),
                      cy = std::min(ry, p.domains_per_side - 1);
            double best = std::numeric_limits<double>::infinity();
            Transform chosen;
            for (int by = std::max(0, cy - reach);
                 by <= std::min(p.domains_per_side - 1, cy + reach); ++by)
                for (int bx = std::max(0, cx - reach);
                     bx <= std::min(p.domains_per_side - 1, cx + reach); ++bx) {
                    double error = 0.0;
                    Transform t =
                        fit(r, r_sum, domains[size_t(by) * p.domains_per_side + bx], error);
                    if (error < best) {
                        best = error;
                        t.domain_x = bx;
                        t.domain_y = by;
                        chosen = t;
                    }
                }
            transforms[size_t(ry) * p.ranges_per_side + rx] = chosen;
        }
    return transforms;
}

void decodeAttractor(const std::vector<Transform>& transforms, const Partition& p, int iterations,
                     const uint16_t* pinned, const uint8_t* pinned_mask, uint16_t* out)
{
    decodeIterates(transforms, p, iterations, pinned, pinned_mask,
                   [&](int i, const uint16_t* codes) {
                       if (i == iterations)
                           std::copy_n(codes, size_t(p.n) * p.n, out);
                   });
}

void decodeIterates(const std::vector<Transform>& transforms, const Partition& p, int iterations,
                    const uint16_t* pinned, const uint8_t* pinned_mask,
                    const std::function<void(int, const uint16_t*)>& each)
{
    const int m = p.side;
    std::vector<int32_t> f(size_t(m) * m), next(size_t(m) * m);
    std::vector<uint16_t> codes(size_t(p.n) * p.n);
    const auto pin = [&](std::vector<int32_t>& image) {
        if (!pinned)
            return;
        for (int y = 0; y < p.n; ++y)
            for (int x = 0; x < p.n; ++x)
                if (pinned_mask[size_t(y) * p.n + x])
                    image[size_t(y) * m + x] = int32_t(pinned[size_t(y) * p.n + x])
                                               << kFractionBits;
    };
    const auto emit = [&](int i) {
        for (int y = 0; y < p.n; ++y)
            for (int x = 0; x < p.n; ++x)
                codes[size_t(y) * p.n + x] = uint16_t(std::min(
                    floorDiv(f[size_t(y) * m + x] + (1 << (kFractionBits - 1)), 1 << kFractionBits),
                    65535));
        each(i, codes.data());
    };
    // f_0: each range block at its fixed point o / (1 − s).
    for (int ry = 0; ry < p.ranges_per_side; ++ry)
        for (int rx = 0; rx < p.ranges_per_side; ++rx) {
            const Transform& t = transforms[size_t(ry) * p.ranges_per_side + rx];
            const int32_t value = std::clamp(
                floorDiv(t.o * (kScaleDenominator << kFractionBits), kScaleDenominator - t.s), 0,
                kMaxValue);
            for (int v = 0; v < kRangeSide; ++v)
                std::fill_n(&f[size_t(ry * kRangeSide + v) * m + rx * kRangeSide], kRangeSide,
                            value);
        }
    pin(f);
    emit(0);
    // f_{i+1} = T f_i: p = s · (mean of 2 × 2 of D) + o, in 1/16 code.
    for (int i = 0; i < iterations; ++i) {
        for (int ry = 0; ry < p.ranges_per_side; ++ry)
            for (int rx = 0; rx < p.ranges_per_side; ++rx) {
                const Transform& t = transforms[size_t(ry) * p.ranges_per_side + rx];
                for (int v = 0; v < kRangeSide; ++v)
                    for (int u = 0; u < kRangeSide; ++u) {
                        const int32_t* d = &f[size_t(t.domain_y * kRangeSide + 2 * v) * m +
                                              t.domain_x * kRangeSide + 2 * u];
                        const int32_t sum4 = d[0] + d[1] + d[m] + d[m + 1];
                        const int32_t value = floorDiv(t.s * sum4, 4 * kScaleDenominator) +
                                              t.o * (1 << kFractionBits);
                        next[size_t(ry * kRangeSide + v) * m + rx * kRangeSide + u] =
                            std::clamp(value, 0, kMaxValue);
                    }
            }
        f.swap(next);
        pin(f);
        emit(i + 1);
    }
}

} // namespace ridge::fractal
