// The jpeg2000 codec (include/ridge/codec/jpeg2000_codec.h): payload, the paper's rate
// control (Figure 7) and the decoder.
#include "ridge/codec/jpeg2000_codec.h"

#include "difference_layer.h"
#include "j2k_image.h"
#include "ridge/codec/codec_registry.h"
#include "ridge/codec/progressive_tokens.h"
#include "ridge/core/error.h"

#include <zstd.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>

namespace ridge {

using jpeg2000::Quantizer;
using jpeg2000::Region;

namespace {

constexpr uint8_t kMagic = 'J';
constexpr uint8_t kPayloadVersion = 1;
constexpr size_t kHeaderSize = 17;
constexpr uint8_t kReversibleFlag = 1;
// Limits on the stored quantizer: |d_min| and the top value stay within what 16-bit codes
// and their predictions can differ by, so that no arithmetic below can overflow.
constexpr int64_t kMaxDifference = 2 * 65535;
// Rate search (Figure 7): bisection steps over the library's rate parameter.
constexpr int kSearchSteps = 8;

j2k::Library libraryOf(Jpeg2000Library l)
{
    return l == Jpeg2000Library::Htj2k ? j2k::Library::Htj2k : j2k::Library::OpenJpeg;
}

// One coded version of a patch, its reconstruction and what it costs.
struct Coded {
    jpeg2000::Quantizer quantizer;
    Jpeg2000Encoding kind = Jpeg2000Encoding::Direct;
    bool reversible = true;
    std::vector<uint8_t> codestream;
    std::vector<uint8_t> border;         // zstd frame of the edge deltas
    std::vector<uint16_t> region_values; // final reconstruction over the region
    size_t bytes() const { return kHeaderSize + border.size() + codestream.size(); }
};

// The exact region, its prediction and the criterion, fixed for one patch and kind.
struct PatchProblem {
    Region region;
    int e = 0;      // max-abs bound of every sample
    int edge_e = 0; // the edges' bound, floor(E): the same for every patch
    CompressionCriterion criterion = CompressionCriterion::MaxAbs;
    double rms_bound = 0;       // E for the RMS criterion
    std::vector<int32_t> exact; // heights over the region
    std::vector<int32_t> prediction;
};

void putU32(uint8_t* p, uint32_t v)
{
    for (int k = 0; k < 4; ++k)
        p[k] = static_cast<uint8_t>(v >> (8 * k));
}

uint32_t getU32(const uint8_t* p)
{
    return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}

ZSTD_CCtx* threadCCtx()
{
    thread_local std::unique_ptr<ZSTD_CCtx, size_t (*)(ZSTD_CCtx*)> ctx(ZSTD_createCCtx(),
                                                                        ZSTD_freeCCtx);
    return ctx.get();
}

ZSTD_DCtx* threadDCtx()
{
    thread_local std::unique_ptr<ZSTD_DCtx, size_t (*)(ZSTD_DCtx*)> ctx(ZSTD_createDCtx(),
                                                                        ZSTD_freeDCtx);
    return ctx.get();
}

uint32_t zigzag(int32_t v)
{
    return (uint32_t(v) << 1) ^ uint32_t(v >> 31);
}
int32_t unzigzag(uint32_t u)
{
    return int32_t(u >> 1) ^ -int32_t(u & 1);
}

// Final values over the region from the decoded image d̂ (edges from their deltas, or,
// while encoding, from the exact heights, recording the deltas).
void reconstructRegion(const PatchProblem* problem, const Region& r, const Quantizer& q,
                       const int32_t* image, const int32_t* prediction, int e,
                       std::vector<int32_t>* deltas, const int32_t* given_deltas, uint16_t* values)
{
    size_t edge = 0;
    const int32_t s = 2 * e + 1;
    for (int y = 0; y < r.height; ++y)
        for (int x = 0; x < r.width; ++x) {
            const size_t i = size_t(y) * r.width + x;
            const int64_t coded = int64_t(prediction[i]) + q.dequantize(image[i]);
            if (!r.onEdge(x, y)) {
                values[i] = jpeg2000::clampCode(coded);
                continue;
            }
            const int32_t guess =
                jpeg2000::edgeIndex(int32_t(jpeg2000::clampCode(coded)) - prediction[i], e);
            int32_t index;
            if (problem) {
                index = jpeg2000::edgeIndex(problem->exact[i] - prediction[i], e);
                deltas->push_back(index - guess);
            } else {
                index = guess + given_deltas[edge];
            }
            ++edge;
            values[i] = jpeg2000::clampCode(int64_t(prediction[i]) + int64_t(index) * s);
        }
}

bool meetsCriterion(const PatchProblem& p, const uint16_t* values)
{
    const size_t n = p.region.count();
    int64_t worst = 0;
    double squares = 0;
    for (size_t i = 0; i < n; ++i) {
        const int64_t d = std::abs(int64_t(values[i]) - p.exact[i]);
        worst = std::max(worst, d);
        squares += double(d) * double(d);
    }
    if (p.criterion == CompressionCriterion::Rms)
        return std::sqrt(squares / double(n)) <= p.rms_bound && worst <= p.e;
    return worst <= p.e;
}

std::vector<uint8_t> packBorder(const std::vector<int32_t>& deltas)
{
    std::vector<uint8_t> raw;
    raw.reserve(deltas.size());
    for (int32_t d : deltas)
        progressive_tokens::putVarint(raw, zigzag(d));
    std::vector<uint8_t> out(ZSTD_compressBound(raw.size()));
    const size_t n =
        ZSTD_compressCCtx(threadCCtx(), out.data(), out.size(), raw.data(), raw.size(), 19);
    if (ZSTD_isError(n))
        throw Error("internal error: zstd failed on a jpeg2000 edge stream");
    out.resize(n);
    return out;
}

size_t edgeCount(const Region& r)
{
    size_t n = 0;
    for (int y = 0; y < r.height; ++y)
        for (int x = 0; x < r.width; ++x)
            n += r.onEdge(x, y);
    return n;
}

// Decodes the edge stream: exactly `count` deltas, each within ±2^17, nothing after.
bool unpackBorder(const uint8_t* src, size_t size, size_t count, std::vector<int32_t>* deltas)
{
    const unsigned long long content = ZSTD_getFrameContentSize(src, size);
    if (content == ZSTD_CONTENTSIZE_ERROR || content == ZSTD_CONTENTSIZE_UNKNOWN ||
        content > 4 * count || ZSTD_findFrameCompressedSize(src, size) != size)
        return false;
    std::vector<uint8_t> raw(static_cast<size_t>(content));
    const size_t n = ZSTD_decompressDCtx(threadDCtx(), raw.data(), raw.size(), src, size);
    if (ZSTD_isError(n) || n != raw.size())
        return false;
    deltas->clear();
    const uint8_t *p = raw.data(), *end = raw.data() + raw.size();
    for (size_t k = 0; k < count; ++k) {
        uint32_t u = 0;
        if (!progressive_tokens::getVarint(p, end, u) || u > (1u << 18))
            return false;
        deltas->push_back(unzigzag(u));
    }
    return p == end;
}

// One encode at `rate`, decoded back and measured; false when the library fails or the
// criterion does not hold.
bool tryRate(const PatchProblem& p, const Quantizer& q, Jpeg2000Encoding kind, j2k::Library lib,
             const std::vector<int32_t>& image, j2k::Rate rate, Coded* out)
{
    const Region& r = p.region;
    std::string error;
    Coded c;
    c.quantizer = q;
    c.kind = kind;
    c.reversible = rate.reversible;
    if (!j2k::encode(lib, image.data(), r.width, r.height, q.bits, rate, &c.codestream, &error))
        throw Error("jpeg2000 codec: " + error);
    std::vector<int32_t> decoded(r.count());
    if (!j2k::decode(lib, c.codestream.data(), c.codestream.size(), r.width, r.height, q.bits,
                     decoded.data(), &error, /*trusted=*/true))
        throw Error("jpeg2000 codec: cannot decode its own codestream: " + error);
    std::vector<int32_t> deltas;
    c.region_values.resize(r.count());
    reconstructRegion(&p, r, q, decoded.data(), p.prediction.data(), p.edge_e, &deltas, nullptr,
                      c.region_values.data());
    if (!meetsCriterion(p, c.region_values.data()))
        return false;
    c.border = packBorder(deltas);
    *out = std::move(c);
    return true;
}

// Figure 7 for one kind: the quantization depth, then the smallest codestream whose
// reconstruction meets the criterion. False when no depth up to 16 bits can.
bool searchKind(PatchProblem& p, Jpeg2000Encoding kind, const Jpeg2000Variant& v, Coded* best)
{
    const Region& r = p.region;
    const size_t n = r.count();
    int32_t lo = INT32_MAX, hi = INT32_MIN;
    for (size_t i = 0; i < n; ++i) {
        const int32_t d = p.exact[i] - p.prediction[i];
        lo = std::min(lo, d);
        hi = std::max(hi, d);
    }
    // Depth: the paper's (8 for D, 12 direct), more where quantization alone breaks the
    // criterion (a range too wide for the bound's steps).
    const int base = kind == Jpeg2000Encoding::Progressive ? Jpeg2000Variant::kDifferenceBits
                                                           : Jpeg2000Variant::kDirectBits;
    std::vector<int32_t> image(n);
    std::vector<uint16_t> values(n);
    std::vector<int32_t> unused;
    Quantizer q;
    bool fits = false;
    for (int bits = base; bits <= 16 && !fits; ++bits) {
        q = Quantizer::fit(lo, hi, bits);
        for (size_t i = 0; i < n; ++i)
            image[i] = q.quantize(p.exact[i] - p.prediction[i]);
        unused.clear();
        reconstructRegion(&p, r, q, image.data(), p.prediction.data(), p.edge_e, &unused, nullptr,
                          values.data());
        fits = meetsCriterion(p, values.data());
    }
    if (!fits)
        return false;

    const j2k::Library lib = libraryOf(v.library);
    // The reversible wavelet reproduces d̂, which meets the criterion: the search's floor.
    if (!tryRate(p, q, kind, lib, image, {true, 0}, best))
        throw Error("internal error: the reversible jpeg2000 path missed its criterion");
    if (v.criterion == CompressionCriterion::Lossless)
        return true;
    // Bisection on the logarithm of the rate parameter: OpenJPEG's compression ratio
    // (1..512 against the n-bit raw image), OpenJPH's relative quantization step
    // (2^-16..2^-1). Larger compresses more; keep the smallest passing codestream.
    double lo_log, hi_log;
    if (lib == j2k::Library::OpenJpeg) {
        lo_log = 0.0;
        hi_log = 9.0;
    } else {
        lo_log = -16.0;
        hi_log = -1.0;
    }
    for (int step = 0; step < kSearchSteps; ++step) {
        const double mid = 0.5 * (lo_log + hi_log);
        Coded c;
        if (tryRate(p, q, kind, lib, image, {false, std::exp2(mid)}, &c)) {
            if (c.bytes() < best->bytes())
                *best = std::move(c);
            lo_log = mid;
        } else {
            hi_log = mid;
        }
    }
    return true;
}

Coded encodeRegion(const uint16_t* codes, const PatchContext& ctx, const Jpeg2000Variant& v, int e,
                   int edge_e, double criterion_value)
{
    PatchProblem p;
    p.region = Region::of(ctx);
    p.e = e;
    p.edge_e = edge_e;
    p.criterion = v.criterion;
    p.rms_bound = criterion_value;
    const Region& r = p.region;
    p.exact.resize(r.count());
    for (int y = 0; y < r.height; ++y)
        for (int x = 0; x < r.width; ++x)
            p.exact[size_t(y) * r.width + x] = codes[size_t(y) * r.patch_size + x];
    p.prediction.resize(r.count());
    Coded best;
    if (ctx.parent && v.encoding == Jpeg2000Encoding::Progressive) {
        jpeg2000::predictFine(ctx, r, p.prediction.data());
        if (searchKind(p, Jpeg2000Encoding::Progressive, v, &best))
            return best;
        // D's range is too wide for 16 bits at this bound (only when e = 0): code the
        // heights themselves, whose range always fits.
    }
    std::fill(p.prediction.begin(), p.prediction.end(), 0);
    if (!searchKind(p, Jpeg2000Encoding::Direct, v, &best))
        throw Error("internal error: a direct jpeg2000 patch missed its criterion at 16 bits");
    return best;
}

void expand(const Region& r, const uint16_t* region_values, uint16_t* patch)
{
    for (int y = 0; y < r.height; ++y)
        std::copy(region_values + size_t(y) * r.width, region_values + size_t(y + 1) * r.width,
                  patch + size_t(y) * r.patch_size);
    jpeg2000::extendRegion(r, patch);
}

} // namespace

// ---- variant ---------------------------------------------------------------------------

int Jpeg2000Variant::bits() const
{
    return int(encoding) | int(criterion) << 1 | int(library) << 3;
}

std::optional<Jpeg2000Variant> Jpeg2000Variant::fromBits(int bits)
{
    if (bits < 0 || bits > 15 || ((bits >> 1) & 3) == 3)
        return std::nullopt;
    Jpeg2000Variant v;
    v.encoding = Jpeg2000Encoding(bits & 1);
    v.criterion = CompressionCriterion((bits >> 1) & 3);
    v.library = Jpeg2000Library((bits >> 3) & 1);
    return v;
}

std::optional<Jpeg2000Variant> Jpeg2000Variant::fromName(const std::string& name)
{
    Jpeg2000Variant v;
    const bool valid = forEachSpecOption(name, "jpeg2000", [&](const auto& key, const auto& value) {
        if (key == "encoding" && (value == "progressive" || value == "direct"))
            v.encoding =
                value == "direct" ? Jpeg2000Encoding::Direct : Jpeg2000Encoding::Progressive;
        else if (key == "criterion" && value == "max")
            v.criterion = CompressionCriterion::MaxAbs;
        else if (key == "criterion" && value == "rms")
            v.criterion = CompressionCriterion::Rms;
        else if (key == "criterion" && value == "lossless")
            v.criterion = CompressionCriterion::Lossless;
        else if (key == "library" && (value == "openjpeg" || value == "htj2k"))
            v.library = value == "htj2k" ? Jpeg2000Library::Htj2k : Jpeg2000Library::OpenJpeg;
        else
            return false;
        return true;
    });
    return valid ? std::optional(v) : std::nullopt;
}

std::string Jpeg2000Variant::describe() const
{
    static const char* criteria[] = {"max-abs", "rms", "lossless residuals"};
    return std::string(encoding == Jpeg2000Encoding::Direct ? "direct" : "progressive") + ", " +
           criteria[int(criterion)] + ", " + j2k::libraryName(libraryOf(library));
}

// ---- codec -----------------------------------------------------------------------------

Jpeg2000Codec::Jpeg2000Codec(double criterion_value, int level_count, Jpeg2000Variant variant)
    : criterion_(criterion_value), variant_(variant)
{
    const bool lossless = variant.criterion == CompressionCriterion::Lossless;
    if (!(std::isfinite(criterion_value) && criterion_value >= 0 && criterion_value <= 32767) ||
        (!lossless && !(criterion_value > 0)))
        throw Error("jpeg2000 codec: the criterion's E must be a number in (0, 32767] codes (got " +
                    std::to_string(criterion_value) + ")");
    if (level_count < 1 || level_count > 32)
        throw Error("jpeg2000 codec: 1 to 32 levels");
    const double bound = variant.criterion == CompressionCriterion::Rms
                             ? criterion_value * Jpeg2000Variant::kRmsGuardFactor
                             : criterion_value;
    sample_bound_ = static_cast<int>(std::min(32767.0, std::floor(bound)));
    edge_bound_ = static_cast<int>(std::floor(criterion_value));
}

double Jpeg2000Codec::levelErrorBound(int) const
{
    return sample_bound_;
}

bool Jpeg2000Codec::needsParent(int level) const
{
    return level > 0 && variant_.encoding == Jpeg2000Encoding::Progressive;
}

// Every patch decodes on the GPU (§4): the residual add from the parent's resident codes,
// or from 0 for the root and direct patches.
CodecCapabilities Jpeg2000Codec::capabilities() const
{
    const bool progressive = variant_.encoding == Jpeg2000Encoding::Progressive;
    return {progressive, {0, progressive, false, progressive, true}};
}

int Jpeg2000Codec::decodeForGpu(const uint8_t* src, size_t src_size, const PatchContext& ctx,
                                std::shared_ptr<const GpuPayload>* out) const
{
    auto d = std::make_shared<Jpeg2000Difference>();
    if (const int status = decodeDifference(src, src_size, ctx, d.get()); status != kCodecOk)
        return status;
    *out = std::move(d);
    return kCodecOk;
}

int Jpeg2000Codec::finishOnCpu(const GpuPayload& payload, const PatchContext& ctx,
                               uint16_t* dst) const
{
    const auto* d = dynamic_cast<const Jpeg2000Difference*>(&payload);
    if (!d || ctx.patch_size < 3)
        return kCodecBadHeader;
    // addPrediction indexes the image by the coded region and the edges by the patch side.
    const Region r = Region::of(ctx);
    const size_t n = size_t(ctx.patch_size);
    const bool shaped = d->width == r.width && d->height == r.height &&
                        d->image.size() == r.count() && d->top.size() == n &&
                        d->bottom.size() == n && d->left.size() == n && d->right.size() == n;
    if (!shaped || d->bits < 1 || d->bits > 16 ||
        (d->kind == Jpeg2000Encoding::Progressive && !needsParent(ctx.level)))
        return kCodecBadHeader;
    if (d->kind == Jpeg2000Encoding::Progressive && !ctx.parent)
        return kCodecNeedsParent;
    addPrediction(*d, ctx, dst);
    return kCodecOk;
}

void Jpeg2000Codec::storeParameters(double param[2]) const
{
    param[0] = criterion_;
    param[1] = variant_.bits();
}

size_t Jpeg2000Codec::encodeBound(const PatchContext& ctx) const
{
    // The reversible codestream of 16-bit samples never exceeds twice the raw size plus
    // its headers; the edge stream its zstd bound.
    const size_t n = size_t(ctx.patch_size) * ctx.patch_size;
    return kHeaderSize + ZSTD_compressBound(4 * 4 * size_t(ctx.patch_size)) + 4 * n + 4096;
}

size_t Jpeg2000Codec::encode(uint8_t* dst, size_t dst_capacity, const uint16_t* codes,
                             const PatchContext& ctx) const
{
    const PatchContext c =
        needsParent(ctx.level) ? ctx : PatchContext{ctx.patch_size, ctx.level,    nullptr, 0,
                                                    ctx.samples_x,  ctx.samples_y};
    if (needsParent(ctx.level) && !ctx.parent)
        throw Error("jpeg2000 codec: a patch below the root needs its parent's reconstruction");
    const Coded coded = encodeRegion(codes, c, variant_, sample_bound_, edge_bound_, criterion_);
    if (coded.bytes() > dst_capacity)
        return 0;
    dst[0] = kMagic;
    dst[1] = kPayloadVersion;
    dst[2] = uint8_t(coded.kind);
    dst[3] = uint8_t(coded.quantizer.bits);
    dst[4] = coded.reversible ? kReversibleFlag : 0;
    putU32(dst + 5, uint32_t(coded.quantizer.d_min));
    putU32(dst + 9, coded.quantizer.step);
    putU32(dst + 13, uint32_t(coded.border.size()));
    std::memcpy(dst + kHeaderSize, coded.border.data(), coded.border.size());
    std::memcpy(dst + kHeaderSize + coded.border.size(), coded.codestream.data(),
                coded.codestream.size());
    return coded.bytes();
}

void Jpeg2000Codec::reconstruct(const uint16_t* codes, const PatchContext& ctx, uint16_t* out) const
{
    const PatchContext c =
        needsParent(ctx.level) ? ctx : PatchContext{ctx.patch_size, ctx.level,    nullptr, 0,
                                                    ctx.samples_x,  ctx.samples_y};
    const Coded coded = encodeRegion(codes, c, variant_, sample_bound_, edge_bound_, criterion_);
    expand(Region::of(ctx), coded.region_values.data(), out);
}

int Jpeg2000Codec::decodeDifference(const uint8_t* src, size_t src_size, const PatchContext& ctx,
                                    Jpeg2000Difference* out) const
{
    if (src_size < kHeaderSize)
        return kCodecTruncated;
    if (src[0] != kMagic || src[1] != kPayloadVersion || src[2] > 1 || src[3] < 1 || src[3] > 16 ||
        (src[4] & ~kReversibleFlag))
        return kCodecBadHeader;
    const auto kind = Jpeg2000Encoding(src[2]);
    // A patch below the root of a progressive archive may be direct (the fallback), never
    // the other way round: the root and a direct archive have no parent to predict from.
    if (kind == Jpeg2000Encoding::Progressive && !needsParent(ctx.level))
        return kCodecBadHeader;
    Quantizer q;
    q.bits = src[3];
    q.d_min = int32_t(getU32(src + 5));
    q.step = getU32(src + 9);
    const int64_t floor_min = kind == Jpeg2000Encoding::Direct ? 0 : -kMaxDifference;
    const int64_t ceiling = kind == Jpeg2000Encoding::Direct ? 65535 : kMaxDifference;
    // Quantizer::fit never makes a step above range / (2^n - 1) + 1; with that, d_min +
    // d̂·step stays far inside int32 for every d̂ the image can hold.
    const int64_t max_step = (ceiling - floor_min) / q.top() + 1;
    if (q.step < 1 || q.d_min < floor_min || q.d_min > ceiling || q.step > max_step)
        return kCodecBadHeader;
    const uint32_t border_bytes = getU32(src + 13);
    if (border_bytes > src_size - kHeaderSize)
        return kCodecTruncated;
    const Region r = Region::of(ctx);
    std::vector<int32_t> deltas;
    if (!unpackBorder(src + kHeaderSize, border_bytes, edgeCount(r), &deltas))
        return kCodecCorrupt;
    const uint8_t* stream = src + kHeaderSize + border_bytes;
    const size_t stream_size = src_size - kHeaderSize - border_bytes;
    if (stream_size == 0)
        return kCodecTruncated;
    // The codestream runs to the end of the payload: bytes after its EOC marker are refused,
    // as the other codecs refuse trailing bytes (neither library notices them).
    std::string error;
    const size_t codestream = j2k::codestreamSize(stream, stream_size, &error);
    if (codestream == 0)
        return kCodecCorrupt;
    if (codestream != stream_size)
        return kCodecTrailingBytes;
    // Said before decoding, so that an intact HTJ2K archive does not read as corrupt.
    if (variant_.library == Jpeg2000Library::Htj2k && !j2k::htj2kDecodingAllowed())
        return kCodecDisabled;
    std::vector<int32_t> image(r.count());
    if (!j2k::decode(libraryOf(variant_.library), stream, stream_size, r.width, r.height, q.bits,
                     image.data(), &error))
        return kCodecCorrupt;

    // The edges' final differences from P need P: they are defined relative to the
    // JPEG 2000 value, so resolve them against the prediction here.
    out->kind = kind;
    out->bits = q.bits;
    out->width = r.width;
    out->height = r.height;
    out->d_min = q.d_min;
    out->step = q.step;
    out->image.assign(image.begin(), image.end());
    std::vector<int32_t> prediction(r.count());
    PatchContext pc = ctx;
    if (kind == Jpeg2000Encoding::Direct)
        pc.parent = nullptr;
    else if (!ctx.parent)
        return kCodecNeedsParent;
    jpeg2000::predictFine(pc, r, prediction.data());
    std::vector<uint16_t> values(r.count());
    reconstructRegion(nullptr, r, q, image.data(), prediction.data(), edge_bound_, nullptr,
                      deltas.data(), values.data());
    const int n = ctx.patch_size;
    for (auto* edge : {&out->top, &out->bottom, &out->left, &out->right})
        edge->assign(size_t(n), 0);
    for (int y = 0; y < r.height; ++y)
        for (int x = 0; x < r.width; ++x) {
            if (!r.onEdge(x, y))
                continue;
            const size_t i = size_t(y) * r.width + x;
            const int32_t d = int32_t(values[i]) - prediction[i];
            if (y == 0)
                out->top[x] = d;
            if (y == n - 1)
                out->bottom[x] = d;
            if (x == 0)
                out->left[y] = d;
            if (x == n - 1)
                out->right[y] = d;
        }
    return kCodecOk;
}

void Jpeg2000Codec::addPrediction(const Jpeg2000Difference& d, const PatchContext& ctx,
                                  uint16_t* dst)
{
    const Region r{ctx.patch_size, d.width, d.height};
    PatchContext pc = ctx;
    if (d.kind == Jpeg2000Encoding::Direct)
        pc.parent = nullptr;
    std::vector<int32_t> prediction(r.count());
    jpeg2000::predictFine(pc, r, prediction.data());
    Quantizer q;
    q.bits = d.bits;
    q.d_min = d.d_min;
    q.step = d.step;
    const int n = ctx.patch_size;
    for (int y = 0; y < r.height; ++y)
        for (int x = 0; x < r.width; ++x) {
            const size_t i = size_t(y) * r.width + x;
            int64_t v;
            if (y == 0)
                v = d.top[x];
            else if (y == n - 1)
                v = d.bottom[x];
            else if (x == 0)
                v = d.left[y];
            else if (x == n - 1)
                v = d.right[y];
            else
                v = q.dequantize(d.image[i]);
            dst[size_t(y) * n + x] = jpeg2000::clampCode(prediction[i] + v);
        }
    jpeg2000::extendRegion(r, dst);
}

int Jpeg2000Codec::decode(uint16_t* dst, const uint8_t* src, size_t src_size,
                          const PatchContext& ctx) const
{
    Jpeg2000Difference d;
    const int status = decodeDifference(src, src_size, ctx, &d);
    if (status != kCodecOk)
        return status;
    addPrediction(d, ctx, dst);
    return kCodecOk;
}

} // namespace ridge
