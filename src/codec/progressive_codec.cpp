#include "ridge/codec/progressive_codec.h"

#include "progressive_entropy.h"
#include "ridge/core/error.h"

#include <cstring>
#include <vector>

namespace ridge {

namespace {

constexpr uint8_t kMagic = 'P';
constexpr uint8_t kVersion = 1;
constexpr size_t kHeaderSize = 2;

// Per-thread scratch: patches are coded concurrently by the build and the streamer.
struct Scratch {
    std::vector<int32_t> q, parent_q, residuals;
    std::vector<uint8_t> bytes;
    void resize(int n)
    {
        const size_t samples = static_cast<size_t>(n) * n;
        q.resize(samples);
        parent_q.resize(samples);
        residuals.resize(samples);
    }
};

Scratch& scratch(int n)
{
    thread_local Scratch s;
    s.resize(n);
    return s;
}

// The parent's decoded codes at the child's step: the base its R samples refine. Encoder and
// decoder both derive it from the reconstruction, so they always agree.
void requantizeParent(const LevelQuantizer& quant, const uint16_t* parent, size_t samples,
                      int32_t* base)
{
    for (size_t i = 0; i < samples; ++i)
        base[i] = quant.quantize(parent[i]);
}

bool validPatchSize(int n)
{
    return n >= 3 && n <= 4097 && ((n - 1) & (n - 2)) == 0;
}

} // namespace

int ProgressiveVariant::bits() const
{
    return (predictor == OddPredictor::Cubic ? 2 : 0) | (contexts ? 4 : 0);
}

ProgressiveVariant ProgressiveVariant::fromBits(int bits)
{
    return {(bits & 2) ? OddPredictor::Cubic : OddPredictor::Bilinear, (bits & 4) != 0};
}

std::string ProgressiveVariant::describe() const
{
    return std::string(predictor == OddPredictor::Cubic ? "cubic" : "bilinear") + " prediction, " +
           (contexts ? "activity contexts" : "no contexts");
}

ProgressiveCodec::ProgressiveCodec(double max_error, int level_count, ProgressiveVariant variant)
    : max_error_(max_error), finest_level_(level_count - 1), variant_(variant)
{
    if (!(max_error >= 0 && max_error <= 32767))
        throw Error("progressive codec: max error " + std::to_string(max_error) +
                    " codes is outside 0..32767");
    if (level_count < 1 || level_count > 32)
        throw Error("progressive codec: bad level count " + std::to_string(level_count));
}

LevelQuantizer ProgressiveCodec::quantizer(int level) const
{
    return LevelQuantizer::make(max_error_, finest_level_ - level);
}

double ProgressiveCodec::levelErrorBound(int level) const
{
    return quantizer(level).bound;
}

size_t ProgressiveCodec::encodeBound(const PatchContext& ctx) const
{
    // Worst case per residual: a 15-bit token, 5 + 20 escape bits and a 15-bit sign.
    const size_t samples = static_cast<size_t>(ctx.patch_size) * ctx.patch_size;
    return kHeaderSize + samples * 8 + 16;
}

void ProgressiveCodec::storeParameters(double param[2]) const
{
    param[0] = max_error_;
    param[1] = variant_.bits();
}

void ProgressiveCodec::reconstruct(const uint16_t* codes, const PatchContext& ctx,
                                   uint16_t* out) const
{
    const LevelQuantizer quant = quantizer(ctx.level);
    const size_t samples = static_cast<size_t>(ctx.patch_size) * ctx.patch_size;
    for (size_t i = 0; i < samples; ++i)
        out[i] = quant.reconstruct(quant.quantize(codes[i]));
}

size_t ProgressiveCodec::encode(uint8_t* dst, size_t dst_capacity, const uint16_t* codes,
                                const PatchContext& ctx) const
{
    const int n = ctx.patch_size;
    if (!validPatchSize(n) || ctx.level < 0 || ctx.level > finest_level_ ||
        (ctx.level > 0 && !ctx.parent))
        return 0;
    Scratch& s = scratch(n);
    const size_t samples = static_cast<size_t>(n) * n;
    const LevelQuantizer quant = quantizer(ctx.level);
    for (size_t i = 0; i < samples; ++i)
        s.q[i] = quant.quantize(codes[i]);

    const ResidualCoding coding{ctx.level == 0, variant_.contexts};
    if (coding.root) {
        rootResiduals(s.q.data(), n, s.residuals.data());
    } else {
        requantizeParent(quant, ctx.parent, samples, s.parent_q.data());
        childResiduals(s.q.data(), s.parent_q.data(), ctx.child_index, n, variant_.predictor,
                       s.residuals.data());
    }
    s.bytes.clear();
    s.bytes.push_back(kMagic);
    s.bytes.push_back(kVersion);
    encodeResiduals(s.residuals.data(), n, coding, s.bytes);
    if (s.bytes.size() > dst_capacity)
        return 0;
    std::memcpy(dst, s.bytes.data(), s.bytes.size());
    return s.bytes.size();
}

bool ProgressiveCodec::validContext(const PatchContext& ctx) const
{
    return validPatchSize(ctx.patch_size) && ctx.level >= 0 && ctx.level <= finest_level_ &&
           ctx.child_index >= 0 && ctx.child_index <= 3;
}

int ProgressiveCodec::entropyDecode(const uint8_t* src, size_t src_size, const PatchContext& ctx,
                                    int32_t* residuals) const
{
    if (src_size < kHeaderSize)
        return kCodecTruncated;
    if (src[0] != kMagic || src[1] != kVersion)
        return kCodecBadHeader;
    const ResidualCoding coding{ctx.level == 0, variant_.contexts};
    return ::ridge::decodeResiduals(src + kHeaderSize, src_size - kHeaderSize, ctx.patch_size,
                                    coding, residuals);
}

int ProgressiveCodec::decodeResiduals(const uint8_t* src, size_t src_size, const PatchContext& ctx,
                                      int32_t* residuals) const
{
    if (!validContext(ctx) || ctx.level == 0)
        return kCodecBadHeader;
    return entropyDecode(src, src_size, ctx, residuals);
}

int ProgressiveCodec::decode(uint16_t* dst, const uint8_t* src, size_t src_size,
                             const PatchContext& ctx) const
{
    if (!validContext(ctx))
        return kCodecBadHeader;
    if (ctx.level > 0 && !ctx.parent)
        return kCodecNeedsParent;

    // 1. Entropy decoding (CPU): the residual grid.
    const int n = ctx.patch_size;
    Scratch& s = scratch(n);
    const int status = entropyDecode(src, src_size, ctx, s.residuals.data());
    if (status != kCodecOk)
        return status;

    // 2. Reconstruction (GPU-able): refine + predict + add, then bins to heights.
    const size_t samples = static_cast<size_t>(n) * n;
    const LevelQuantizer quant = quantizer(ctx.level);
    if (ctx.level == 0) {
        reconstructRoot(s.residuals.data(), n, s.q.data());
    } else {
        requantizeParent(quant, ctx.parent, samples, s.parent_q.data());
        reconstructChild(s.residuals.data(), s.parent_q.data(), ctx.child_index, n,
                         variant_.predictor, s.q.data());
    }
    for (size_t i = 0; i < samples; ++i)
        dst[i] = quant.reconstruct(s.q[i]);
    return kCodecOk;
}

} // namespace ridge
