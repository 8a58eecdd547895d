#pragma once
// Reconstruction half of the progressive codec: refine + predict + add, on quantized bins.
//
// This is the part the hardware-tessellation paper runs on the GPU; the entropy decoding
// (progressive_entropy) stays on the CPU and produces the residual grid consumed here. It
// is integer arithmetic only (adds, shifts, no division), each pass data-parallel over its
// samples, so a compute shader can run the passes as written.
//
// A child patch of n = 2^m + 1 samples covers one quadrant of its parent. In child
// coordinates (fig. 4 of the paper):
//   R  (even x, even y): refined parent samples, q = base + r, r the refinement and base
//                        the parent's reconstruction requantized at the child's step;
//   A  (odd x,  even y): predicted along the row from R;
//   B  (even x, odd y):  predicted along the column from R;
//   C  (odd x,  odd y):  predicted from A and B (Cubic) or from the 4 diagonal R (Bilinear).
// Prediction errors follow the paper's sign: d = P − q, so q = P − d.
// The coarsest patch has no parent; it is predicted in raster order by the median edge
// detector of LOCO-I (the paper codes it "directly"; MED makes that cheap).
#include <algorithm>
#include <cstdint>

namespace ridge {

enum class OddPredictor : uint8_t {
    Bilinear = 0, // the paper: mean of the 2 (A, B) or 4 (C) nearest refined samples
    Cubic = 1,    // 4-tap cubic (−1, 9, 9, −1)/16; quadratic at patch borders; C averages
                  // the row and column cubics through the A and B samples
};

enum class SampleClass : uint8_t { R = 0, A = 1, B = 2, C = 3 };

inline SampleClass sampleClass(int x, int y)
{
    return static_cast<SampleClass>((x & 1) | ((y & 1) << 1));
}

// The samples a patch codes: [0, width) × [0, height). Both odd, so the region ends on R
// samples that its parent holds, and >= 3. v1 codes whole patches; v2 codes what covers the
// level's valid extent (PatchContext::samples_x/y rounded up to odd) and reconstructs the
// padding beyond by repeating the last coded column and row (replicateBeyond), which is the
// edge extension the pyramid itself pads with. Predictions read only coded samples: the
// cubic's line ends where the region does.
struct CodedRegion {
    int width = 0;
    int height = 0;

    static CodedRegion whole(int n) { return {n, n}; }
    // The region of a patch of side n that must hold `samples_x` × `samples_y` samples
    // (0 = all n).
    static CodedRegion covering(int n, int samples_x, int samples_y)
    {
        auto side = [n](int s) { return s <= 0 || s >= n ? n : std::max(3, s | 1); };
        return {side(samples_x), side(samples_y)};
    }
    bool isWhole(int n) const { return width == n && height == n; }
};

// Least-squares corrections of the A, B and C predictions (v2; learned per archive and
// level, stored with the codec tables). Where all 12 taps of a class lie inside the coded
// region, P = P0 + (Σ w_i · clamp(s_i − P0, ±32767) + 2048) >> 12, with P0 the predictor's
// (cubic or bilinear) value and s_i the known samples at kCorrectionTaps[class]; elsewhere,
// or with all weights 0 (v1), P = P0. |w_i| <= 4095 keeps the sum inside int32, so a GPU
// computes it in 32-bit integers exactly as the CPU does.
inline constexpr int kCorrectionTapCount = 12;
inline constexpr int kMaxCorrectionWeight = 4095;
struct CorrectionTap {
    int dx, dy;
};
// [class − 1][tap]: A from the R samples of its row and the rows 2 above and below; B from
// the R samples of its column and the columns 2 aside, and the 4 diagonal A samples; C from
// its 2 A and 2 B neighbours, the 4 diagonal R samples and the A, B samples 3 away.
inline constexpr CorrectionTap kCorrectionTaps[3][kCorrectionTapCount] = {
    {{-1, 0},
     {1, 0},
     {-3, 0},
     {3, 0},
     {-1, -2},
     {1, -2},
     {-1, 2},
     {1, 2},
     {-3, -2},
     {3, -2},
     {-3, 2},
     {3, 2}},
    {{0, -1},
     {0, 1},
     {0, -3},
     {0, 3},
     {-2, -1},
     {2, -1},
     {-2, 1},
     {2, 1},
     {-1, -1},
     {1, -1},
     {-1, 1},
     {1, 1}},
    {{0, -1},
     {0, 1},
     {-1, 0},
     {1, 0},
     {-1, -1},
     {1, -1},
     {-1, 1},
     {1, 1},
     {0, -3},
     {0, 3},
     {-3, 0},
     {3, 0}},
};
// The margin each class's taps need inside the region: x in [mx, w − mx), y in [my, h − my).
inline constexpr int kCorrectionMarginX[3] = {3, 2, 3};
inline constexpr int kCorrectionMarginY[3] = {2, 3, 3};

struct PredictorWeights {
    int16_t w[3][kCorrectionTapCount] = {}; // [class − 1]; all 0 = no correction
    bool any() const
    {
        for (const auto& c : w)
            for (int16_t v : c)
                if (v)
                    return true;
        return false;
    }
};

// The correction at (x, y) of class `cls` (1..3) given P0; 0 outside the interior.
int32_t predictionCorrection(const int32_t* q, int n, const CodedRegion& region, int x, int y,
                             int cls, int32_t p0, const PredictorWeights& weights);

// P at (x, y) of class A, B or C, from the samples of q that earlier passes completed.
int32_t predictOdd(const int32_t* q, int n, const CodedRegion& region, int x, int y,
                   OddPredictor predictor, const PredictorWeights* weights = nullptr);
// MED prediction of the coarsest patch at (x, y) from its west, north, north-west samples.
int32_t predictRoot(const int32_t* q, int n, int x, int y);

// Encoder side: residuals[n·n] of a child patch from its bins q and `parent_base`, the
// parent's reconstruction requantized at the child's step (n·n, the whole parent patch;
// quadrant `child_index` = (x & 1) | (y & 1) << 1 of the child's position). Zero outside
// the region.
void childResiduals(const int32_t* q, const int32_t* parent_base, int child_index, int n,
                    const CodedRegion& region, OddPredictor predictor, int32_t* residuals,
                    const PredictorWeights* weights = nullptr);
void rootResiduals(const int32_t* q, int n, const CodedRegion& region, int32_t* residuals);

// Decoder side: the exact inverses. Write q[n·n] inside the region (replicateBeyond fills
// the rest).
void reconstructChild(const int32_t* residuals, const int32_t* parent_base, int child_index, int n,
                      const CodedRegion& region, OddPredictor predictor, int32_t* q,
                      const PredictorWeights* weights = nullptr);
void reconstructRoot(const int32_t* residuals, int n, const CodedRegion& region, int32_t* q);
// Samples beyond the region repeat the nearest one inside: q(x, y) = q(min(x, w−1),
// min(y, h−1)). Nothing to do for a whole region.
void replicateBeyond(int32_t* q, int n, const CodedRegion& region);

} // namespace ridge
