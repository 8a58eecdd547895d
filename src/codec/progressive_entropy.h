#pragma once
// Entropy half of the progressive codec: residual grid <-> range-coded bytes (CPU side).
//
// Symbols (the paper's, with the alphabet made fast):
//   refinements r at R samples: {−1, 0, +1} + an escape for anything else (a Neville pyramid
//     or clamped padding can break the nesting; the bound never depends on it);
//   prediction errors d at A, B, C samples (and all samples of the coarsest patch):
//     magnitude token 0..15 — |d| < 8 directly, then 7 octaves [8·2^k, 16·2^k) followed by
//     k + 3 raw bits, then an escape with a 5-bit length — and, when d != 0, an adaptive sign.
// Context modelling (the paper: "simple context modeling can improve the compression"):
// each magnitude is coded with one of 12 activity classes per sample class, the activity
// being the mean magnitude of already-decoded residuals around the sample. Contexts use
// residuals only, never heights, so entropy decoding needs nothing from the reconstruction
// and the two halves stay separable (CPU decode, GPU reconstruct).
#include "ridge/codec/progressive_reconstruction.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace ridge {

struct ResidualCoding {
    bool root = false;    // coarsest patch: one MED class in raster order
    bool contexts = true; // activity contexts (false: one model per sample class)
};

// Largest residual magnitude the format carries (larger ones are corrupt input).
constexpr int32_t kMaxResidual = 1 << 20;

// Appends the coded residual grid (n·n) to `out`.
void encodeResiduals(const int32_t* residuals, int n, const ResidualCoding& coding,
                     std::vector<uint8_t>& out);

// Decodes exactly `size` bytes into residuals[n·n]. Returns 0 or a negative CodecStatus.
int decodeResiduals(const uint8_t* data, size_t size, int n, const ResidualCoding& coding,
                    int32_t* residuals);

} // namespace ridge
