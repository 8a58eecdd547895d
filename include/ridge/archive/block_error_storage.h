#pragma once
// Storage of tessellation block errors λ(d) inside a patch blob.
//
// λ (metres) is stored as uint16 units of a per-patch quantum, rounded up so a stored bound is
// never smaller than the computed one. The quantum is max(height_scale / 16, largest λ /
// 65533), so every value fits without saturation and small λ keep 1/16-code precision; it is
// chosen per patch so that a streaming build needs no global statistics first. Layout:
// f32 quantum (metres), then one zstd frame of the uint16 array (blocks row-major, d fastest):
// ~3x smaller than raw, which matters next to lossy payloads.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace ridge::archive {

// Quantizes λ given in code units (computeTessellationBlockErrors) and compresses them.
std::vector<uint8_t> packBlockErrors(const float* lambda_codes, size_t count, double height_scale);

// Decompresses into `count` metres values (kBlockErrorSaturated becomes +infinity). Returns
// false when the bytes are not a valid quantum followed by exactly one zstd frame of `count`
// uint16 values.
bool unpackBlockErrors(const uint8_t* data, size_t size, size_t count, float* lambda_metres);

} // namespace ridge::archive
