#include "difference_layer.h"

#include <algorithm>

namespace ridge::jpeg2000 {

Region Region::of(const PatchContext& ctx)
{
    const int n = ctx.patch_size;
    const auto covered = [n](int s) { return s > 0 && s <= n ? s : n; };
    return {n, covered(ctx.samples_x), covered(ctx.samples_y)};
}

void predictFine(const PatchContext& ctx, const Region& r, int32_t* prediction)
{
    if (!ctx.parent) {
        std::fill(prediction, prediction + r.count(), 0);
        return;
    }
    const int n = r.patch_size, half = (n - 1) / 2;
    const int ox = (ctx.child_index & 1) * half, oy = (ctx.child_index >> 1) * half;
    const uint16_t* parent = ctx.parent;
    for (int y = 0; y < r.height; ++y) {
        // Parent rows above and below the child sample (the same row when y is even).
        const uint16_t* a = parent + size_t(oy + y / 2) * n + ox;
        const uint16_t* b = (y & 1) ? a + n : a;
        int32_t* out = prediction + size_t(y) * r.width;
        for (int x = 0; x < r.width; ++x) {
            const int i = x / 2, j = i + (x & 1);
            out[x] = (int32_t(a[i]) + a[j] + b[i] + b[j] + 2) >> 2;
        }
    }
}

Quantizer Quantizer::fit(int32_t lo, int32_t hi, int bits)
{
    Quantizer q;
    q.bits = bits;
    q.d_min = lo;
    const int64_t levels = (int64_t(1) << bits) - 1, range = int64_t(hi) - lo;
    q.step = static_cast<uint32_t>(std::max<int64_t>(1, (range + levels - 1) / levels));
    return q;
}

int32_t Quantizer::quantize(int32_t d) const
{
    const int64_t q = (int64_t(d) - d_min + step / 2) / step;
    return static_cast<int32_t>(std::clamp<int64_t>(q, 0, top()));
}

void extendRegion(const Region& r, uint16_t* patch)
{
    const int n = r.patch_size;
    for (int y = 0; y < r.height; ++y)
        std::fill(patch + size_t(y) * n + r.width, patch + size_t(y + 1) * n,
                  patch[size_t(y) * n + r.width - 1]);
    for (int y = r.height; y < n; ++y)
        std::copy(patch + size_t(r.height - 1) * n, patch + size_t(r.height) * n,
                  patch + size_t(y) * n);
}

} // namespace ridge::jpeg2000
