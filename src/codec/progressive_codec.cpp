#include "ridge/codec/progressive_codec.h"

#include "predictor_fit.h"
#include "progressive_entropy.h"
#include "progressive_entropy_v2.h"
#include "ridge/core/error.h"
#include "ridge/core/target_clones.h"

#include <algorithm>
#include <cstring>
#include <functional>
#include <limits>
#include <mutex>
#include <vector>

namespace ridge {

namespace {

constexpr uint8_t kMagic = 'P';
constexpr size_t kHeaderSize = 2;   // magic, payload version
constexpr size_t kV2HeaderSize = 3; // + flags
constexpr uint8_t kV2RefinementsCoded = 1;

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
// decoder both derive it from the reconstruction, so they always agree. Only the child's
// quadrant of the parent is read (parentBin), so only it is requantized.
void requantizeParent(const LevelQuantizer& quant, const uint16_t* parent, int n, int child_index,
                      int32_t* base)
{
    const int half = (n - 1) / 2;
    const int x0 = (child_index & 1) * half, y0 = (child_index >> 1) * half;
    for (int y = y0; y <= y0 + half; ++y)
        for (int x = x0; x <= x0 + half; ++x) {
            const size_t i = static_cast<size_t>(y) * n + x;
            base[i] = quant.quantize(parent[i]);
        }
}

// dst[i] = quant.reconstruct(q[i]) in 32-bit arithmetic, so that it vectorises: a bin is
// clamped to [0, 65535 / step + 1] first, where step · bin stays below 2^18 and the clamp to
// 65535 that follows gives what the 64-bit product would.
RIDGE_TARGET_CLONES
void reconstructCodes(const LevelQuantizer& quant, const int32_t* __restrict q, size_t count,
                      uint16_t* __restrict dst)
{
    const int32_t step = static_cast<int32_t>(quant.step);
    const int32_t top = 65535 / step + 1;
    for (size_t i = 0; i < count; ++i)
        dst[i] = static_cast<uint16_t>(std::min(step * std::clamp(q[i], 0, top), 65535));
}

bool validPatchSize(int n)
{
    return n >= 3 && n <= 4097 && ((n - 1) & (n - 2)) == 0;
}

} // namespace

int ProgressiveVariant::bits() const
{
    const int common = (predictor == OddPredictor::Cubic ? 2 : 0) | (contexts ? 4 : 0);
    if (format == 1)
        return common;
    return common | 8 | (nested_levels << 4) | (format == 3 ? kPayloadV3Bit : 0) |
           (format == 4 ? kPayloadV4Bit : 0);
}

std::optional<ProgressiveVariant> ProgressiveVariant::fromBits(int bits)
{
    if (bits < 0 || (bits & 1) || bits >= 2 * kPayloadV4Bit)
        return std::nullopt;
    const bool v3 = (bits & kPayloadV3Bit) != 0, v4 = (bits & kPayloadV4Bit) != 0;
    if ((v3 || v4) && !(bits & 8)) // v3 and v4 are kinds of v2
        return std::nullopt;
    if (v3 && v4)
        return std::nullopt;
    ProgressiveVariant v{(bits & 2) ? OddPredictor::Cubic : OddPredictor::Bilinear, (bits & 4) != 0,
                         v4           ? 4
                         : v3         ? 3
                         : (bits & 8) ? 2
                                      : 1,
                         (bits & (kPayloadV3Bit - 1)) >> 4};
    if (v.format == 1) {
        if (v.nested_levels != 0)
            return std::nullopt;
        v.nested_levels = 1;
    } else if (v.nested_levels < 1 || v.nested_levels > 32) {
        return std::nullopt;
    }
    return v;
}

std::string ProgressiveVariant::describe() const
{
    std::string text = std::string(predictor == OddPredictor::Cubic ? "cubic" : "bilinear") +
                       " prediction, " + (contexts ? "activity contexts" : "no contexts");
    if (format == 1)
        return text + ", payload v1 (adaptive range coding, bounds doubling per level)";
    return text + ", payload v" + std::to_string(format) + " (static tables, rANS" +
           (format == 3   ? " with row contexts, "
            : format == 4 ? " with row and parent-class contexts, "
                          : ", ") +
           std::to_string(nested_levels) + " nested levels at the finest bound)";
}

ProgressiveCodec::ProgressiveCodec(double max_error, int level_count, ProgressiveVariant variant)
    : max_error_(max_error), finest_level_(level_count - 1), variant_(variant)
{
    if (!(max_error >= 0 && max_error <= 32767))
        throw Error("progressive codec: max error " + std::to_string(max_error) +
                    " codes is outside 0..32767");
    if (level_count < 1 || level_count > 32)
        throw Error("progressive codec: bad level count " + std::to_string(level_count));
    if (!ProgressiveVariant::fromBits(variant.bits()))
        throw Error("progressive codec: invalid variant (nested_levels " +
                    std::to_string(variant.nested_levels) + ")");
    tables_ = ProgressiveTables::defaults(level_count, variant_.tableContexts());
}

void ProgressiveCodec::setTables(std::shared_ptr<const ProgressiveTables> tables, bool complete)
{
    if (!tables || tables->levelCount() != finest_level_ + 1)
        throw Error("progressive codec: tables for another level count");
    if (variant_.format >= 2 && tables->contexts() != variant_.tableContexts())
        throw Error("progressive codec: tables for another payload version");
    tables_ = std::move(tables);
    training_stage_ = complete ? 2 : 1;
}

void ProgressiveCodec::bins(const uint16_t* codes, const PatchContext& ctx, int32_t* q) const
{
    const LevelQuantizer quant = quantizer(ctx.level);
    const size_t samples = static_cast<size_t>(ctx.patch_size) * ctx.patch_size;
    for (size_t i = 0; i < samples; ++i)
        q[i] = quant.quantize(codes[i]);
}

std::vector<uint8_t> ProgressiveCodec::storeTables() const
{
    return variant_.format >= 2 ? tables_->serialize() : std::vector<uint8_t>{};
}

LevelQuantizer ProgressiveCodec::quantizer(int level) const
{
    // v2: the nested_levels finest levels share the finest bound, coarser ones double from it.
    const int k = finest_level_ - level;
    return LevelQuantizer::make(max_error_, std::max(0, k - (variant_.nested_levels - 1)));
}

CodedRegion ProgressiveCodec::codedRegion(const PatchContext& ctx) const
{
    if (variant_.format == 1)
        return CodedRegion::whole(ctx.patch_size);
    return CodedRegion::covering(ctx.patch_size, ctx.samples_x, ctx.samples_y);
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
    const int n = ctx.patch_size;
    const CodedRegion region = codedRegion(ctx);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            // Padding beyond the coded region repeats its last column and row (replicateBeyond).
            const size_t from = static_cast<size_t>(std::min(y, region.height - 1)) * n +
                                std::min(x, region.width - 1);
            out[static_cast<size_t>(y) * n + x] = quant.reconstruct(quant.quantize(codes[from]));
        }
}

bool ProgressiveCodec::residualsOf(const uint16_t* codes, const PatchContext& ctx,
                                   int32_t* residuals, int32_t* parent_bins) const
{
    const int n = ctx.patch_size;
    if (!validContext(ctx) || (ctx.level > 0 && !ctx.parent))
        return false;
    Scratch& s = scratch(n);
    const size_t samples = static_cast<size_t>(n) * n;
    const LevelQuantizer quant = quantizer(ctx.level);
    for (size_t i = 0; i < samples; ++i)
        s.q[i] = quant.quantize(codes[i]);
    const CodedRegion region = codedRegion(ctx);
    if (ctx.level == 0) {
        rootResiduals(s.q.data(), n, region, residuals);
    } else {
        requantizeParent(quant, ctx.parent, n, ctx.child_index, parent_bins);
        childResiduals(s.q.data(), parent_bins, ctx.child_index, n, region, variant_.predictor,
                       residuals, weights(ctx.level));
    }
    return true;
}

namespace {

// v2: are any of a child's refinements non-zero? (Inside the nested zone they never are.)
bool hasRefinements(const int32_t* residuals, int n, const CodedRegion& region)
{
    for (int y = 0; y < region.height; y += 2)
        for (int x = 0; x < region.width; x += 2)
            if (residuals[static_cast<size_t>(y) * n + x] != 0)
                return true;
    return false;
}

// How the codec's payload v2..v4 entropy-codes a patch whose residuals an encoder has.
ResidualCodingV2 residualCoding(const ProgressiveCodec& codec, const PatchContext& ctx,
                                const int32_t* residuals, const int32_t* parent_bins)
{
    ResidualCodingV2 coding{codec.variant().format, ctx.level, ctx.level == 0,
                            codec.codedRegion(ctx), true};
    coding.refinements = !coding.root && hasRefinements(residuals, ctx.patch_size, coding.region);
    if (!coding.root && coding.version == 4) {
        coding.parent_bins = parent_bins;
        coding.child_index = ctx.child_index;
    }
    return coding;
}

} // namespace

size_t ProgressiveCodec::encode(uint8_t* dst, size_t dst_capacity, const uint16_t* codes,
                                const PatchContext& ctx) const
{
    const int n = ctx.patch_size;
    if (!validPatchSize(n))
        return 0;
    Scratch& s = scratch(n);
    if (!residualsOf(codes, ctx, s.residuals.data(), s.parent_q.data()))
        return 0;
    s.bytes.clear();
    s.bytes.push_back(kMagic);
    s.bytes.push_back(static_cast<uint8_t>(variant_.format));
    if (variant_.format == 1) {
        const ResidualCoding coding{ctx.level == 0, variant_.contexts};
        encodeResiduals(s.residuals.data(), n, coding, s.bytes);
    } else {
        const ResidualCodingV2 coding =
            residualCoding(*this, ctx, s.residuals.data(), s.parent_q.data());
        s.bytes.push_back(coding.refinements ? kV2RefinementsCoded : 0);
        if (!encodeResidualsV2(s.residuals.data(), n, coding, *tables_, s.bytes))
            return 0;
    }
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
                                    int32_t* residuals, const int32_t* parent_bins) const
{
    if (src_size < kHeaderSize)
        return kCodecTruncated;
    if (src[0] != kMagic || src[1] != variant_.format)
        return kCodecBadHeader;
    if (variant_.format == 1) {
        const ResidualCoding coding{ctx.level == 0, variant_.contexts};
        return ::ridge::decodeResiduals(src + kHeaderSize, src_size - kHeaderSize, ctx.patch_size,
                                        coding, residuals);
    }
    if (src_size < kV2HeaderSize)
        return kCodecTruncated;
    const uint8_t flags = src[2];
    if ((flags & ~kV2RefinementsCoded) || (ctx.level == 0 && flags != 0))
        return kCodecBadHeader;
    ResidualCodingV2 coding{variant_.format, ctx.level, ctx.level == 0, codedRegion(ctx),
                            (flags & kV2RefinementsCoded) != 0};
    if (variant_.format == 4 && !coding.root) {
        // v4's contexts read the parent's bins at this level's step (decode() has them).
        if (!ctx.parent)
            return kCodecNeedsParent;
        if (!parent_bins) {
            thread_local std::vector<int32_t> requantized;
            requantized.resize(static_cast<size_t>(ctx.patch_size) * ctx.patch_size);
            requantizeParent(quantizer(ctx.level), ctx.parent, ctx.patch_size, ctx.child_index,
                             requantized.data());
            parent_bins = requantized.data();
        }
        coding.parent_bins = parent_bins;
        coding.child_index = ctx.child_index;
    }
    return decodeResidualsV2(src + kV2HeaderSize, src_size - kV2HeaderSize, ctx.patch_size, coding,
                             *tables_, residuals);
}

int ProgressiveCodec::decodeResiduals(const uint8_t* src, size_t src_size, const PatchContext& ctx,
                                      int32_t* residuals) const
{
    if (!validContext(ctx) || ctx.level == 0)
        return kCodecBadHeader;
    return entropyDecode(src, src_size, ctx, residuals);
}

int ProgressiveCodec::decodeForGpu(const uint8_t* src, size_t src_size, const PatchContext& ctx,
                                   std::shared_ptr<const GpuPayload>* out) const
{
    if (!validContext(ctx))
        return kCodecBadHeader;
    std::vector<int32_t> wide(size_t(ctx.patch_size) * size_t(ctx.patch_size));
    if (const int status = decodeResiduals(src, src_size, ctx, wide.data()); status != kCodecOk)
        return status;
    auto payload = std::make_shared<ProgressiveResiduals>();
    payload->assign(std::move(wide));
    payload->region = codedRegion(ctx);
    *out = std::move(payload);
    return kCodecOk;
}

void ProgressiveResiduals::assign(std::vector<int32_t> values)
{
    const bool narrow = std::all_of(values.begin(), values.end(), [](int32_t v) {
        return v >= std::numeric_limits<int16_t>::min() && v <= std::numeric_limits<int16_t>::max();
    });
    residuals16.clear();
    residuals32.clear();
    if (narrow)
        residuals16.assign(values.begin(), values.end());
    else
        residuals32 = std::move(values);
}

void ProgressiveResiduals::widen(int32_t* out) const
{
    if (residuals32.empty())
        std::copy(residuals16.begin(), residuals16.end(), out);
    else
        std::copy(residuals32.begin(), residuals32.end(), out);
}

std::vector<int32_t> ProgressiveResiduals::wide() const
{
    std::vector<int32_t> out(count());
    widen(out.data());
    return out;
}

int ProgressiveCodec::decode(uint16_t* dst, const uint8_t* src, size_t src_size,
                             const PatchContext& ctx) const
{
    if (!validContext(ctx))
        return kCodecBadHeader;
    if (ctx.level > 0 && !ctx.parent)
        return kCodecNeedsParent;

    // 0. The parent's bins at this level's step: v4's contexts read them, the reconstruction
    // refines them.
    const int n = ctx.patch_size;
    Scratch& s = scratch(n);
    const LevelQuantizer quant = quantizer(ctx.level);
    if (ctx.level > 0)
        requantizeParent(quant, ctx.parent, n, ctx.child_index, s.parent_q.data());

    // 1. Entropy decoding (CPU): the residual grid.
    const int status = entropyDecode(src, src_size, ctx, s.residuals.data(),
                                     ctx.level > 0 ? s.parent_q.data() : nullptr);
    if (status != kCodecOk)
        return status;

    // 2. Reconstruction (GPU-able): refine + predict + add, then bins to heights.
    reconstructPatch(s.residuals.data(), s.parent_q.data(), ctx, dst);
    return kCodecOk;
}

void ProgressiveCodec::reconstructPatch(const int32_t* residuals, const int32_t* parent_bins,
                                        const PatchContext& ctx, uint16_t* dst) const
{
    const int n = ctx.patch_size;
    std::vector<int32_t>& q = scratch(n).q; // callers pass the scratch's other grids
    const CodedRegion region = codedRegion(ctx);
    if (ctx.level == 0) {
        reconstructRoot(residuals, n, region, q.data());
    } else {
        reconstructChild(residuals, parent_bins, ctx.child_index, n, region, variant_.predictor,
                         q.data(), weights(ctx.level));
    }
    replicateBeyond(q.data(), n, region);
    reconstructCodes(quantizer(ctx.level), q.data(), q.size(), dst);
}

// What the GPU decoder does with the residuals (shaders/progressive_reconstruct.comp), here in the
// reconstruction decode() runs, which the GPU path matches bit for bit.
int ProgressiveCodec::finishOnCpu(const GpuPayload& payload, const PatchContext& ctx,
                                  uint16_t* dst) const
{
    const auto* residuals = dynamic_cast<const ProgressiveResiduals*>(&payload);
    if (!validContext(ctx) || ctx.level == 0 || !residuals)
        return kCodecBadHeader;
    if (!ctx.parent)
        return kCodecNeedsParent;
    const int n = ctx.patch_size;
    const size_t samples = static_cast<size_t>(n) * n;
    const CodedRegion region = codedRegion(ctx);
    if (residuals->region.width != region.width || residuals->region.height != region.height ||
        residuals->count() != samples)
        return kCodecBadHeader;
    Scratch& s = scratch(n);
    requantizeParent(quantizer(ctx.level), ctx.parent, n, ctx.child_index, s.parent_q.data());
    residuals->widen(s.residuals.data());
    reconstructPatch(s.residuals.data(), s.parent_q.data(), ctx, dst);
    return kCodecOk;
}

namespace {

// Counts the symbols of every observed patch; fits the tables when done.
class ProgressiveTrainer final : public CodecTrainer {
  public:
    explicit ProgressiveTrainer(
        const ProgressiveCodec& codec, int level_count,
        std::function<bool(const uint16_t*, const PatchContext&, int32_t*, int32_t*)> residuals)
        : codec_(codec), counts_(level_count, codec.variant().tableContexts()),
          residuals_(std::move(residuals))
    {
    }

    void observe(const uint16_t* codes, const PatchContext& ctx) override
    {
        thread_local std::vector<int32_t> residuals, parent_bins;
        residuals.resize(static_cast<size_t>(ctx.patch_size) * ctx.patch_size);
        parent_bins.resize(residuals.size());
        if (!residuals_(codes, ctx, residuals.data(), parent_bins.data()))
            throw Error("progressive codec: cannot train on a patch it cannot encode");
        const ResidualCodingV2 coding =
            residualCoding(codec_, ctx, residuals.data(), parent_bins.data());
        std::lock_guard<std::mutex> lock(mutex_);
        if (!countResidualsV2(residuals.data(), ctx.patch_size, coding, counts_))
            throw Error("progressive codec: a residual is beyond the codable range");
    }

    std::unique_ptr<HeightCodec> finish() override
    {
        auto trained = std::make_unique<ProgressiveCodec>(codec_);
        trained->setTables(ProgressiveTables::fit(counts_, &codec_.tables()));
        return trained;
    }

    std::vector<uint8_t> saveObservations() const override
    {
        std::lock_guard<std::mutex> lock(mutex_);
        return counts_.serialize();
    }

    void mergeObservations(const uint8_t* data, size_t size) override
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (!counts_.mergeSerialized(data, size))
            throw Error("progressive codec: symbol counts of " + std::to_string(size) +
                        " bytes are not this archive's (another codec, level count or stage)");
    }

  private:
    const ProgressiveCodec& codec_;
    mutable std::mutex mutex_;
    SymbolCounts counts_;
    std::function<bool(const uint16_t*, const PatchContext&, int32_t*, int32_t*)> residuals_;
};

// Stage 1: fits the least-squares predictor corrections on the patches' exact bins.
class CorrectionTrainer final : public CodecTrainer {
  public:
    explicit CorrectionTrainer(const ProgressiveCodec& codec, int level_count)
        : codec_(codec), fit_(level_count), level_count_(level_count)
    {
    }

    void observe(const uint16_t* codes, const PatchContext& ctx) override
    {
        if (ctx.level == 0)
            return;
        thread_local std::vector<int32_t> q;
        q.resize(static_cast<size_t>(ctx.patch_size) * ctx.patch_size);
        codec_.bins(codes, ctx, q.data());
        CorrectionFit local(level_count_);
        local.add(q.data(), ctx.patch_size, codec_.codedRegion(ctx), ctx.level,
                  codec_.variant().predictor);
        std::lock_guard<std::mutex> lock(mutex_);
        fit_.merge(local);
    }

    std::unique_ptr<HeightCodec> finish() override
    {
        auto trained = std::make_unique<ProgressiveCodec>(codec_);
        trained->setTables(
            ProgressiveTables::withWeights(fit_.solve(), codec_.variant().tableContexts()), false);
        return trained;
    }

    std::vector<uint8_t> saveObservations() const override
    {
        std::lock_guard<std::mutex> lock(mutex_);
        return fit_.serialize();
    }

    void mergeObservations(const uint8_t* data, size_t size) override
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (!fit_.mergeSerialized(data, size))
            throw Error("progressive codec: correction sums of " + std::to_string(size) +
                        " bytes are not this archive's (another codec, level count or stage)");
    }

  private:
    const ProgressiveCodec& codec_;
    mutable std::mutex mutex_;
    CorrectionFit fit_;
    int level_count_;
};

} // namespace

// Stage 0 is nothing; stages 1 and 2 are the stage byte, then the tables as an archive
// stores them (the corrections alone after stage 1).
std::vector<uint8_t> ProgressiveCodec::trainingState() const
{
    if (training_stage_ == 0)
        return {};
    std::vector<uint8_t> out{static_cast<uint8_t>(training_stage_)};
    const std::vector<uint8_t> tables = tables_->serialize();
    out.insert(out.end(), tables.begin(), tables.end());
    return out;
}

void ProgressiveCodec::restoreTraining(const uint8_t* data, size_t size)
{
    if (size == 0) {
        tables_ = ProgressiveTables::defaults(finest_level_ + 1, variant_.tableContexts());
        training_stage_ = 0;
        return;
    }
    if (variant_.format == 1 || (data[0] != 1 && data[0] != 2))
        throw Error(
            "progressive codec: training state stage " + std::to_string(data[0]) +
            (variant_.format == 1 ? " for payload v1, which learns nothing" : " is not 1 or 2"));
    std::string problem;
    auto tables = ProgressiveTables::parse(data + 1, size - 1, finest_level_ + 1,
                                           variant_.tableContexts(), &problem);
    if (!tables)
        throw Error("progressive codec: training state: " + problem);
    setTables(std::move(tables), data[0] == 2);
}

std::unique_ptr<CodecTrainer> ProgressiveCodec::trainer() const
{
    if (variant_.format == 1 || training_stage_ == 2)
        return nullptr;
    if (training_stage_ == 0 && variant_.corrections)
        return std::make_unique<CorrectionTrainer>(*this, finest_level_ + 1);
    return std::make_unique<ProgressiveTrainer>(
        *this, finest_level_ + 1,
        [this](const uint16_t* codes, const PatchContext& ctx, int32_t* residuals,
               int32_t* parent_bins) { return residualsOf(codes, ctx, residuals, parent_bins); });
}

} // namespace ridge
