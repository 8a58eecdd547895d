#pragma once
// Storage of tessellation block errors λ(d) inside a patch blob.
//
// λ (metres) is stored as uint16 units of the archive's block_error_quantum, rounded up so a
// stored bound is never smaller than the computed one; kBlockErrorSaturated means "too large
// to store: never simplify this block". The uint16 array (blocks row-major, d fastest) is
// compressed as one zstd frame: ~3x smaller than raw, which matters next to lossy payloads.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace ridge::archive {

// Quantizes λ given in code units (computeTessellationBlockErrors) and compresses them.
std::vector<uint8_t> packBlockErrors(const float* lambda_codes, size_t count,
                                     double height_scale, double quantum);

// Decompresses into `count` metres values (saturated entries become +infinity). Returns false
// when the bytes are not exactly one zstd frame of `count` uint16 values.
bool unpackBlockErrors(const uint8_t* data, size_t size, size_t count, double quantum,
                       float* lambda_metres);

} // namespace ridge::archive
