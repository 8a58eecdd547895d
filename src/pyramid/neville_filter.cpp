// Neville-4 coarsening filter.
//
// This work is based on:
//   Yusov, Turlapov: "GPU-optimized efficient quad-tree based progressive multiresolution
//   model for interactive large scale terrain rendering", GraphiCon 2007;
//   Yusov: "High-performance rendering of compressed multiresolution terrain using JPEG2000"
//   (§3.2.1: "order 4 Neville interpolating filter"); Sweldens, "The lifting scheme".
//
// Lifting with the order-4 Neville predictor P(f) = (-f[-3] + 9 f[-1] + 9 f[1] - f[3]) / 16
// for odd samples and the update c = f_even + (d_left + d_right) / 4, which keeps the
// coarse signal's average (a plain subsampling would alias ridges into the coarse levels).
// Expanded, the low-pass is the 9-tap filter (1, 0, -8, 16, 46, 16, -8, 0, 1) / 64.
// Borders use the same edge extension (clamping) as every level's padding.
#include "ridge/pyramid/level_pyramid.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace ridge {

namespace {

constexpr float kTaps[5] = {46.f / 64, 16.f / 64, -8.f / 64, 0.f, 1.f / 64}; // |offset| 0..4

// Filters one line of `n` samples spaced `stride` apart into `m` outputs spaced `out_stride`.
template <typename In, typename Out>
void filterLine(const In* in, int n, int64_t stride, Out* out, int m, int64_t out_stride)
{
    auto sample = [&](int64_t k) {
        return static_cast<float>(in[std::clamp<int64_t>(k, 0, n - 1) * stride]);
    };
    for (int i = 0; i < m; ++i) {
        const int64_t c = 2 * int64_t{i};
        float v = kTaps[0] * sample(c);
        for (int k = 1; k <= 4; ++k)
            if (kTaps[k] != 0.f)
                v += kTaps[k] * (sample(c - k) + sample(c + k));
        if constexpr (std::is_same_v<Out, float>)
            out[i * out_stride] = v;
        else
            out[i * out_stride] = static_cast<Out>(std::clamp(std::lround(v), 0L, 65535L));
    }
}

} // namespace

CodeGrid coarsenNeville4(const CodeGrid& fine)
{
    CodeGrid coarse;
    coarse.width = (fine.width - 1 + 1) / 2 + 1;
    coarse.height = (fine.height - 1 + 1) / 2 + 1;
    // Rows first into a float buffer (fine.height x coarse.width), then columns.
    std::vector<float> rows(static_cast<size_t>(fine.height) * coarse.width);
    for (int y = 0; y < fine.height; ++y)
        filterLine(fine.codes.data() + static_cast<size_t>(y) * fine.width, fine.width, 1,
                   rows.data() + static_cast<size_t>(y) * coarse.width, coarse.width, 1);
    coarse.codes.resize(static_cast<size_t>(coarse.width) * coarse.height);
    for (int x = 0; x < coarse.width; ++x)
        filterLine(rows.data() + x, fine.height, coarse.width, coarse.codes.data() + x,
                   coarse.height, coarse.width);
    return coarse;
}

} // namespace ridge
