#include "predictor_fit.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace ridge {

namespace {

constexpr int T = kCorrectionTapCount;
// Fewer samples than this fit noise rather than terrain; such classes keep weights 0.
constexpr uint64_t kMinSamples = 2048;
// Targets are clamped like the features, so one cliff does not steer a level's weights.
constexpr int64_t kMaxTarget = 16;

// Solves (A + λI) x = b in place by Cholesky; false when A is not positive definite.
bool solveSpd(std::array<double, T * T> a, std::array<double, T> b, std::array<double, T>& x)
{
    double trace = 0;
    for (int i = 0; i < T; ++i)
        trace += a[i * T + i];
    const double ridge = 1e-6 * trace / T + 1e-9;
    for (int i = 0; i < T; ++i)
        a[i * T + i] += ridge;
    for (int j = 0; j < T; ++j) {
        double d = a[j * T + j];
        for (int k = 0; k < j; ++k)
            d -= a[j * T + k] * a[j * T + k];
        if (!(d > 0))
            return false;
        a[j * T + j] = std::sqrt(d);
        for (int i = j + 1; i < T; ++i) {
            double v = a[i * T + j];
            for (int k = 0; k < j; ++k)
                v -= a[i * T + k] * a[j * T + k];
            a[i * T + j] = v / a[j * T + j];
        }
    }
    for (int i = 0; i < T; ++i) { // L y = b
        double v = b[i];
        for (int k = 0; k < i; ++k)
            v -= a[i * T + k] * x[k];
        x[i] = v / a[i * T + i];
    }
    for (int i = T; i-- > 0;) { // Lᵀ x = y
        double v = x[i];
        for (int k = i + 1; k < T; ++k)
            v -= a[k * T + i] * x[k];
        x[i] = v / a[i * T + i];
    }
    return true;
}

} // namespace

CorrectionFit::CorrectionFit(int level_count) : normal_(size_t(std::max(level_count, 0))) {}

void CorrectionFit::add(const int32_t* q, int n, const CodedRegion& region, int level,
                        OddPredictor predictor)
{
    if (level <= 0 || level >= int(normal_.size()))
        return;
    for (int c = 0; c < 3; ++c) {
        Normal& nm = normal_[size_t(level)][size_t(c)];
        const int x0 = ((c + 1) & 1), y0 = ((c + 1) >> 1);
        for (int y = y0; y < region.height; y += 2) {
            if (y < kCorrectionMarginY[c] || y >= region.height - kCorrectionMarginY[c])
                continue;
            for (int x = x0; x < region.width; x += 2) {
                if (x < kCorrectionMarginX[c] || x >= region.width - kCorrectionMarginX[c])
                    continue;
                const int32_t* at = q + static_cast<size_t>(y) * n + x;
                const int32_t p0 = predictOdd(q, n, region, x, y, predictor);
                int64_t f[T];
                for (int i = 0; i < T; ++i) {
                    const CorrectionTap t = kCorrectionTaps[c][i];
                    f[i] =
                        std::clamp(at[t.dy * static_cast<ptrdiff_t>(n) + t.dx] - p0, -32767, 32767);
                }
                const int64_t target =
                    std::clamp<int64_t>(int64_t{*at} - p0, -kMaxTarget, kMaxTarget);
                for (int i = 0; i < T; ++i) {
                    for (int j = 0; j <= i; ++j)
                        nm.ata[i * T + j] += f[i] * f[j];
                    nm.atb[i] += f[i] * target;
                }
                nm.btb += target * target;
                ++nm.count;
            }
        }
    }
}

void CorrectionFit::merge(const CorrectionFit& other)
{
    for (size_t l = 0; l < normal_.size() && l < other.normal_.size(); ++l)
        for (int c = 0; c < 3; ++c) {
            Normal& a = normal_[l][size_t(c)];
            const Normal& b = other.normal_[l][size_t(c)];
            for (size_t k = 0; k < a.ata.size(); ++k)
                a.ata[k] += b.ata[k];
            for (size_t k = 0; k < a.atb.size(); ++k)
                a.atb[k] += b.atb[k];
            a.btb += b.btb;
            a.count += b.count;
        }
}

namespace {

constexpr size_t kSumBytes = 16;
constexpr size_t kNormalSums = 1 + T + 1 + T * (T + 1) / 2; // count, Aᵀb, bᵀb, triangle

// Every sum of one Normal in the stored order, through `visit(Sum&)`.
template <typename Normal, typename Visit> void forEachSum(Normal& nm, Visit&& visit)
{
    visit(nm.count);
    for (auto& v : nm.atb)
        visit(v);
    visit(nm.btb);
    for (int i = 0; i < T; ++i)
        for (int j = 0; j <= i; ++j)
            visit(nm.ata[i * T + j]);
}

} // namespace

std::vector<uint8_t> CorrectionFit::serialize() const
{
    std::vector<uint8_t> out;
    out.reserve(normal_.size() * 3 * kNormalSums * kSumBytes);
    for (const auto& level : normal_)
        for (const Normal& nm : level)
            forEachSum(nm, [&](const Sum& v) {
                const auto u = static_cast<unsigned __int128>(v);
                for (size_t b = 0; b < kSumBytes; ++b)
                    out.push_back(static_cast<uint8_t>(u >> (8 * b)));
            });
    return out;
}

bool CorrectionFit::mergeSerialized(const uint8_t* data, size_t size)
{
    if (size != normal_.size() * 3 * kNormalSums * kSumBytes)
        return false;
    CorrectionFit other(static_cast<int>(normal_.size()));
    size_t at = 0;
    for (auto& level : other.normal_)
        for (Normal& nm : level)
            forEachSum(nm, [&](Sum& v) {
                unsigned __int128 u = 0;
                for (size_t b = 0; b < kSumBytes; ++b)
                    u |= static_cast<unsigned __int128>(data[at + b]) << (8 * b);
                v = static_cast<Sum>(u);
                at += kSumBytes;
            });
    // A count is never negative; the sums of squares neither.
    for (const auto& level : other.normal_)
        for (const Normal& nm : level)
            if (nm.count < 0 || nm.btb < 0)
                return false;
    merge(other);
    return true;
}

std::vector<PredictorWeights> CorrectionFit::solve() const
{
    std::vector<PredictorWeights> out(normal_.size());
    for (size_t l = 1; l < normal_.size(); ++l)
        for (int c = 0; c < 3; ++c) {
            const Normal& nm = normal_[l][size_t(c)];
            if (nm.count < Sum{kMinSamples})
                continue;
            std::array<double, T * T> a{};
            std::array<double, T> atb{};
            for (int i = 0; i < T; ++i) {
                atb[i] = static_cast<double>(nm.atb[i]);
                for (int j = 0; j <= i; ++j) // and the mirror of the lower triangle
                    a[i * T + j] = a[j * T + i] = static_cast<double>(nm.ata[i * T + j]);
            }
            std::array<double, T> x{};
            if (!solveSpd(a, atb, x))
                continue;
            // Rounded weights, and the squared error they leave: keep them only if it drops.
            std::array<double, T> wq{};
            for (int i = 0; i < T; ++i)
                wq[i] = std::clamp(std::round(x[i] * 4096.0), double(-kMaxCorrectionWeight),
                                   double(kMaxCorrectionWeight)) /
                        4096.0;
            const double btb = static_cast<double>(nm.btb);
            double err = btb;
            for (int i = 0; i < T; ++i) {
                err -= 2 * wq[i] * atb[i];
                for (int j = 0; j < T; ++j)
                    err += wq[i] * wq[j] * a[i * T + j];
            }
            if (!(err < btb))
                continue;
            for (int i = 0; i < T; ++i)
                out[l].w[c][i] = static_cast<int16_t>(std::lround(wq[i] * 4096.0));
        }
    return out;
}

} // namespace ridge
