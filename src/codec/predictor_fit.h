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
    // [level] (level 0: none). A class with too few samples, or whose fit does not lower the
    // squared error, keeps weights 0.
    std::vector<PredictorWeights> solve() const;

  private:
    struct Normal {
        std::array<double, kCorrectionTapCount * kCorrectionTapCount> ata{};
        std::array<double, kCorrectionTapCount> atb{};
        double btb = 0;
        uint64_t count = 0;
    };
    std::vector<std::array<Normal, 3>> normal_; // [level][class − 1]
};

} // namespace ridge
