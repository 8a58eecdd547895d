#pragma once
// LOCO-I / JPEG-LS median edge detector (Weinberger et al. 2000), shared by the lossless
// codec, the progressive codec's coarsest patch and the MED+zstd benchmark anchor.
#include <algorithm>
#include <cstddef>
#include <cstdint>

namespace ridge {

// min(w,n) if nw >= max(w,n), max(w,n) if nw <= min(w,n), else w + n - nw: exactly
// median(w, n, w + n - nw), written branch-free.
inline int32_t medPredict(int32_t w, int32_t n, int32_t nw)
{
    return std::clamp(w + n - nw, std::min(w, n), std::max(w, n));
}

// MED at (x, y) of a row-major grid with `width` columns, with ridge's border rule: 0 for
// the first sample, the west neighbour on row 0, the north neighbour on column 0.
template <class T> int32_t medPredictAt(const T* grid, int width, int x, int y)
{
    const T* at = grid + static_cast<size_t>(y) * width + x;
    if (y == 0)
        return x == 0 ? 0 : at[-1];
    if (x == 0)
        return at[-width];
    return medPredict(at[-1], at[-width], at[-width - 1]);
}

} // namespace ridge
