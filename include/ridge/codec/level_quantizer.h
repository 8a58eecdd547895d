#pragma once
// Per-level uniform quantization of the progressive codec ("Quantizing Height Maps", §4 of
// the hardware-tessellation paper), in 16-bit code units.
//
// The paper quantizes level l with step 2δ_l, δ_l = δ_l0 · 2^(l0−l):
//     q = floor((h + δ_l) / 2δ_l),   ĥ = 2δ_l · q,   |ĥ − h| <= δ_l.
// Codes are integers, so ridge sets δ_l0 = e + 1/2 for an integer finest bound e: the step
// s = 2e + 1 is the widest whose bins hold only codes within e of their centre. (δ_l0 = e,
// read literally, would waste log2((2e+1)/2e) bits per sample: 0.58 bits at e = 1.)
// Coarser levels have step s·2^k (k = l0 − l levels above the finest) and bound s·2^(k−1).
//
// Two bin layouts with that same bound at every level:
//   DeadZone (the paper): bins centred on multiples of the step. A parent's bin straddles
//     its children's, so a refined sample takes one of 3 values: q_l = 2·q_{l−1} + {−1,0,+1}.
//   Nested (ridge's default): level l−1's bins are unions of two bins of level l, so
//     q_{l−1} = q_l >> 1 and refinement is one bit. Saves ~0.5 bit per refined sample
//     (a quarter of each level), with reconstructions still one multiply-add.
#include <algorithm>
#include <cstdint>

namespace ridge {

enum class BinLayout : uint8_t { DeadZone = 0, Nested = 1 };

struct LevelQuantizer {
    int64_t step = 1;   // s · 2^k
    int64_t centre = 0; // reconstruction offset inside a bin (Nested); 0 for DeadZone
    int64_t bias = 0;   // quantize: q = floor((h + bias) / step) >> shift
    int shift = 0;
    int bound = 0;      // max |ĥ − h| in codes: e at the finest level, s·2^(k−1) above
    BinLayout layout = BinLayout::Nested;

    // `e`: finest-level bound in codes (>= 0); `k`: levels above the finest (>= 0).
    static LevelQuantizer make(int e, int k, BinLayout layout)
    {
        LevelQuantizer q;
        const int64_t s = 2 * int64_t(e) + 1;
        const int kk = std::min(k, 20); // beyond 2^20·s every code lands in bin 0
        q.layout = layout;
        q.step = s << kk;
        q.bound = static_cast<int>(std::min<int64_t>(kk == 0 ? e : (s << (kk - 1)), 65535));
        if (layout == BinLayout::Nested) {
            // Fine bins [s·q − e, s·q + e]; level k bins are 2^k of them: q_k = q_0 >> k,
            // reconstructed at the lower middle of the union.
            q.bias = e;
            q.shift = kk;
            q.centre = (q.step - 1) / 2 - e;
        } else {
            // q = floor((h + δ) / 2δ) with 2δ = step; for k = 0, δ = e + 1/2 and integer h,
            // floor((h + e + 1/2) / s) = floor((h + e) / s) because s·q − 1/2 is never a code.
            q.bias = kk == 0 ? e : (s << (kk - 1));
            q.shift = 0;
            q.centre = 0;
        }
        return q;
    }

    int32_t quantize(uint16_t code) const
    {
        if (layout == BinLayout::Nested)
            return static_cast<int32_t>((((int64_t(code) + bias) / (step >> shift)) >> shift));
        return static_cast<int32_t>((int64_t(code) + bias) / step);
    }
    uint16_t reconstruct(int32_t q) const
    {
        const int64_t h = step * q + centre;
        return static_cast<uint16_t>(std::clamp<int64_t>(h, 0, 65535));
    }
    // The bin of a reconstructed code: inverse of reconstruct while no clamping happened;
    // encoder and decoder both derive the parent's bins this way, so they always agree.
    int32_t binOf(uint16_t code) const
    {
        const int64_t v = int64_t(code) - centre;
        return static_cast<int32_t>(v < 0 ? 0 : v / step);
    }
};

} // namespace ridge
