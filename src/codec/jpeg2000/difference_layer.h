#pragma once
// The arithmetic of the JPEG2000 paper's model (§3.4), shared by the encoder, the decoder and
// (in GLSL, shaders/jpeg2000_residual_add.comp) the GPU: prediction H̃^Fine, quantization of
// the difference layer D, and ridge's deterministic edge samples. Integers throughout, so
// the CPU and the GPU agree bit for bit.
#include "ridge/codec/height_codec.h"

#include <cstdint>
#include <vector>

namespace ridge::jpeg2000 {

// The region a patch codes: its samples over the valid extent.
struct Region {
    int patch_size = 0;
    int width = 0, height = 0;
    static Region of(const PatchContext& ctx);
    size_t count() const { return size_t(width) * size_t(height); }
    bool onEdge(int x, int y) const
    {
        return x == 0 || y == 0 || x == patch_size - 1 || y == patch_size - 1;
    }
};

// H̃^Fine for child `ctx.child_index` of the parent reconstruction `ctx.parent`: bilinear
// interpolation at the child's samples, rounded half up ((a+b+1)>>1, (a+b+c+d+2)>>2), over
// the region (row-major, width x height). A direct patch (no parent) predicts 0.
void predictFine(const PatchContext& ctx, const Region& r, int32_t* prediction);

// The quantizer of D (or of the heights, direct): value = d_min + d̂ · step, d̂ in
// [0, 2^bits - 1], d̂ = ⌊(d − d_min + step/2) / step⌋. The paper scales by (d^max − d^min)/255;
// ridge rounds that up to a whole step so that dequantization is exact integer arithmetic
// (d^max' = d_min + 255·step ≥ d^max).
struct Quantizer {
    int bits = 8;
    int32_t d_min = 0;
    uint32_t step = 1;
    // The step that fits [lo, hi] into `bits` bits.
    static Quantizer fit(int32_t lo, int32_t hi, int bits);
    int32_t top() const { return (int32_t(1) << bits) - 1; }
    int32_t quantize(int32_t d) const;
    int32_t dequantize(int32_t q) const { return d_min + q * int32_t(step); }
};

// Edge samples: value = P + q·(2e+1), q = ⌊(h − P + e)/(2e+1)⌋, so |value − h| <= e.
inline int32_t edgeIndex(int32_t h_minus_p, int e)
{
    const int32_t s = 2 * e + 1, v = h_minus_p + e;
    return v >= 0 ? v / s : -((-v + s - 1) / s); // floor division
}

inline uint16_t clampCode(int64_t v)
{
    return static_cast<uint16_t>(v < 0 ? 0 : v > 65535 ? 65535 : v);
}

// Repeats the region's last column and row over the rest of the patch.
void extendRegion(const Region& r, uint16_t* patch);

} // namespace ridge::jpeg2000
