#pragma once
// The near-lossless front end shared by the anchors that wrap a lossless coder (JPEG 2000,
// JPEG XL, MED + zstd): integer codes h are mapped to q = floor((h + e) / (2e + 1)) and back
// to (2e + 1) q, clamped to 0..65535. Every h lies in [(2e+1)q - e, (2e+1)q + e], so the
// reconstruction is within e of h; 2e + 1 is the widest step with that property, which makes
// this the strongest scalar quantizer to put in front of a lossless coder for an L-inf bound.
#include "ridge/core/error.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace ridge::codecbench {

inline uint32_t quantizerStep(int max_error)
{
    return 2u * static_cast<uint32_t>(max_error) + 1u;
}

// q fits 16 bits for every e >= 0 (q <= (65535 + e) / (2e + 1) <= 65535).
inline std::vector<uint16_t> quantizeCodes(const uint16_t* codes, size_t count, int max_error)
{
    const uint32_t step = quantizerStep(max_error);
    std::vector<uint16_t> q(count);
    for (size_t i = 0; i < count; ++i)
        q[i] = static_cast<uint16_t>((uint32_t{codes[i]} + uint32_t(max_error)) / step);
    return q;
}

inline uint16_t dequantizeCode(uint32_t q, int max_error)
{
    return static_cast<uint16_t>(std::min<uint64_t>(uint64_t{q} * quantizerStep(max_error), 65535));
}

// Largest q any code can map to: what a decoder may legitimately see.
inline uint32_t maxQuantizedCode(int max_error)
{
    return (65535u + uint32_t(max_error)) / quantizerStep(max_error);
}

// Bits needed for values 0..max_value (at least 1).
inline int bitsFor(uint32_t max_value)
{
    int bits = 1;
    while (bits < 32 && (max_value >> bits) != 0)
        ++bits;
    return bits;
}

// ridge::Error "ANCHOR: PROBLEM", the form every anchor failure takes.
[[noreturn]] inline void anchorFail(const std::string& anchor, const std::string& problem)
{
    throw Error(anchor + ": " + problem);
}

} // namespace ridge::codecbench
