#pragma once
// Least-squares fit of progressive v2's prediction corrections (progressive_reconstruction.h,
// PredictorWeights): per level and class, the 12 weights w minimising Σ (q − P0 − w·f)² over
// the archive's interior samples, f_i = clamp(s_i − P0, ±32767) the taps' differences to the
// base prediction P0. Accumulated from the exact bins (v2 codes bins losslessly, so the
// decoder's neighbours are the encoder's), solved once by Cholesky with a small ridge term,
// rounded to the 12-bit fixed point the reconstruction uses.
#include "ridge/codec/progressive_reconstruction.h"

#include <array>
#include <vector>

namespace ridge {

class CorrectionFit {
  public:
    explicit CorrectionFit(int level_count);
    // The interior samples of one child patch's bins q[n·n] (level > 0).
    void add(const int32_t* q, int n, const CodedRegion& region, int level, OddPredictor predictor);
    void merge(const CorrectionFit& other);
    // The sums as bytes (per level and class: count, then Aᵀb, bᵀb and the lower triangle of
    // AᵀA, each a 128-bit little-endian two's complement integer), and their sum back in:
    // false for bytes that are not such for this level count.
    std::vector<uint8_t> serialize() const;
    bool mergeSerialized(const uint8_t* data, size_t size);
    // [level] (level 0: none). A class with too few samples, or whose fit does not lower the
    // squared error, keeps weights 0.
    std::vector<PredictorWeights> solve() const;

  private:
    // Exact integer sums (features and targets are clamped integers): the fit is the same
    // whatever the order patches are added and merged in, so a build trains the same codec
    // on any number of threads or shards. 128 bits: a planet's finest level can exceed 64.
    __extension__ typedef __int128 Sum;
    struct Normal {
        std::array<Sum, kCorrectionTapCount * kCorrectionTapCount> ata{}; // lower triangle used
        std::array<Sum, kCorrectionTapCount> atb{};
        Sum btb = 0;
        Sum count = 0;
    };
    std::vector<std::array<Normal, 3>> normal_; // [level][class − 1]
};

} // namespace ridge
