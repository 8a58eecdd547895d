#pragma once
// Per-level uniform quantization of the progressive codec ("Quantizing Height Maps", §4 of
// the hardware-tessellation paper), in 16-bit code units.
//
// The paper quantizes level l with step 2δ_l, δ_l = δ_l0 · 2^(l0−l), and refines each
// parent sample by one of {−1, 0, +1} because the steps nest. Codes are integers, so ridge
// takes at each level the widest bins that still hold only codes within the bound:
//     e_k = floor(δ_l0 · 2^k)  (k = l0 − l levels above the finest, δ_l0 in codes),
//     step s_k = 2·e_k + 1,    q = floor((h + e_k) / s_k),   ĥ = s_k · q,   |ĥ − h| <= e_k.
// An odd step is worth log2((2e+1)/2e) bits per sample over the paper's even one (0.58 bits
// at e = 1), and every level keeps the paper's bound δ_l exactly. The price: steps no longer
// nest (s_{k+1} != 2·s_k), so a refined sample is coded against its parent's reconstruction
// requantized at the child's step, r = q − Q_k(ĥ_parent): still {−1, 0, +1} almost always,
// because |ĥ_parent − h| <= e_{k+1} ~ 2·e_k < 1.01 child steps.
#include <algorithm>
#include <cmath>
#include <cstdint>

namespace ridge {

struct LevelQuantizer {
    int64_t step = 1; // s_k = 2·e_k + 1
    int bound = 0;    // e_k: max |ĥ − h| in codes
    // ceil(2^40 / step): floor(x / step) = (x · reciprocal) >> 40 exactly for every
    // x = code + bound < 2^17 (the rounding error x·(reciprocal − 2^40/step)/2^40 stays below
    // 1/step because x · step < 2^34 < 2^40), so the hot loops never divide.
    uint64_t reciprocal = uint64_t(1) << 40;

    // `max_error`: δ_l0 in codes (>= 0, may be fractional); `k`: levels above the finest.
    static LevelQuantizer make(double max_error, int k)
    {
        LevelQuantizer q;
        const double e = std::floor(std::ldexp(max_error, std::min(k, 30)) * (1 + 1e-12) + 1e-9);
        q.bound = static_cast<int>(std::clamp(e, 0.0, 65535.0));
        q.step = 2 * int64_t(q.bound) + 1;
        q.reciprocal = ((uint64_t(1) << 40) + uint64_t(q.step) - 1) / uint64_t(q.step);
        return q;
    }

    int32_t quantize(uint16_t code) const
    {
        return static_cast<int32_t>(((uint64_t(code) + uint64_t(bound)) * reciprocal) >> 40);
    }
    uint16_t reconstruct(int32_t q) const
    {
        return static_cast<uint16_t>(std::clamp<int64_t>(step * q, 0, 65535));
    }
};

} // namespace ridge
