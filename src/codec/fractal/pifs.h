#pragma once
// The partitioned iterated function system (PIFS) of the fractal-rings paper (Erra, Scarano &
// Guida, §7): a patch is partitioned into range blocks of 4 × 4 samples; each range block R is
// coded as R ≈ s·D + o, D a domain block of 8 × 8 samples shrunk by averaging 2 × 2, s and o
// fitted by least squares. Decoding iterates f_{i+1} = T f_i from a fixed start image; the
// iterates approach the attractor of T, close to the patch.
//
// Beyond the paper, the arithmetic is integer so that every decoder (this one, a GPU pass)
// computes the same image bit for bit: f holds heights in 1/16 code (kFractionBits), s is
// quantized to s_q / 32 with |s| ≤ 3/4 (kScaleDenominator, kMaxScale: T stays contractive),
// o is whole codes, and every division rounds down (floorDiv), so nothing depends on how a
// language rounds negative quotients. The start image is each range block's own fixed point
// o / (1 − s) (the height the block settles to when D's mean equals R's), which starts the
// iteration near the patch instead of at 0. Samples given as pinned (the patch's edges, which
// neighbouring patches share) are reset to their values after every iteration.
#include <cstdint>
#include <functional>
#include <vector>

namespace ridge::fractal {

constexpr int kRangeSide = 4;
constexpr int kDomainSide = 2 * kRangeSide;
constexpr int kScaleDenominator = 32;
constexpr int kMaxScale = 24; // |s_q| ≤ 24: |s| ≤ 0.75
constexpr int kFractionBits = 4;
constexpr int32_t kMaxValue = int32_t{65535} << kFractionBits;
constexpr int32_t kMaxOffset = 1 << 20; // |o| in codes: far beyond any fitted offset

// a / b rounded towards −∞, b > 0.
constexpr int32_t floorDiv(int32_t a, int32_t b)
{
    return a >= 0 ? a / b : -((-a + b - 1) / b);
}

// The range and domain grids of a patch of n × n samples: the image is padded to side
// m = 4·⌈n/4⌉ by repeating the last row and column; range blocks tile it, domain blocks start
// on every other range position (overlapping), (m/4 − 1)² of them.
struct Partition {
    int n = 0;
    int side = 0;             // m
    int ranges_per_side = 0;  // m / 4
    int domains_per_side = 0; // m / 4 − 1
    static Partition of(int n);
    int rangeCount() const { return ranges_per_side * ranges_per_side; }
};

// One range block's transform: its domain block (column, row in the domain grid), s_q, o.
struct Transform {
    int32_t domain_x = 0;
    int32_t domain_y = 0;
    int32_t s = 0; // s_q, s = s_q / kScaleDenominator
    int32_t o = 0; // codes
};

// The encoder: per range block in raster order, the transform with the least squared error
// over domain blocks within `search` domain positions of the range's own (0: every domain
// block), ties to the first in raster order. `codes` is the n × n patch.
std::vector<Transform> encodeTransforms(const uint16_t* codes, const Partition& p, int search);

// The decoder: `iterations` (≥ 0) applications of T to the start image; `pinned` (n × n, or
// null) holds a value for every sample with pinned_mask set. Writes n × n codes (the image
// rounded to whole codes). `transforms` must be valid for `p` (checked by the payload
// parser).
void decodeAttractor(const std::vector<Transform>& transforms, const Partition& p, int iterations,
                     const uint16_t* pinned, const uint8_t* pinned_mask, uint16_t* out);
// The same, calling `each(i, codes)` with the image after i = 0..iterations applications (n × n
// codes, valid during the call): every iterate from one decode (the encoder's bound per
// iteration count).
void decodeIterates(const std::vector<Transform>& transforms, const Partition& p, int iterations,
                    const uint16_t* pinned, const uint8_t* pinned_mask,
                    const std::function<void(int, const uint16_t*)>& each);

} // namespace ridge::fractal
