#include "ridge/codec/fractal_codec.h"

#include "pifs.h"
#include "ridge/codec/progressive_tokens.h"
#include "ridge/core/error.h"

#include <zstd.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace ridge {

namespace {

using fractal::Partition;
using fractal::Transform;
// LEB128 varints, as the progressive codec writes its tables.
using progressive_tokens::getVarint;
using progressive_tokens::putVarint;

constexpr uint8_t kMagic = 'F';
constexpr uint8_t kPayloadVersion = 2; // 1: without the bound per iteration count
constexpr size_t kHeaderSize = 14;     // magic, version, iterations, flags, u16 E, 2 × u32 sizes
// v2: then u16 × iterations, the bound of each partial decode (stepBounds).
constexpr int kZstdLevel = 9;
constexpr size_t kMaxVarint = 4;  // getVarint reads values below 2^28
constexpr uint8_t kPaperFlag = 1; // the paper's mode: transforms alone

uint32_t zigzag(int32_t v)
{
    return (uint32_t(v) << 1) ^ uint32_t(v >> 31);
}

int32_t unzigzag(uint32_t u)
{
    return int32_t(u >> 1) ^ -int32_t(u & 1);
}

void putU16(uint8_t* p, uint32_t v)
{
    p[0] = uint8_t(v);
    p[1] = uint8_t(v >> 8);
}

void putU32(uint8_t* p, uint32_t v)
{
    for (int k = 0; k < 4; ++k)
        p[k] = uint8_t(v >> (8 * k));
}

uint32_t getU32(const uint8_t* p)
{
    return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}

// The edge samples of an n × n patch, in payload order: top row, bottom row, then the left
// and right columns without their corners.
std::vector<size_t> edgeOrder(int n)
{
    std::vector<size_t> order;
    order.reserve(size_t(4 * n - 4));
    for (int x = 0; x < n; ++x)
        order.push_back(size_t(x));
    for (int x = 0; x < n; ++x)
        order.push_back(size_t(n - 1) * n + x);
    for (int y = 1; y < n - 1; ++y)
        order.push_back(size_t(y) * n);
    for (int y = 1; y < n - 1; ++y)
        order.push_back(size_t(y) * n + n - 1);
    return order;
}

// Upper bounds of each section's uncompressed bytes (a hostile frame claiming more is
// refused before anything is allocated).
size_t transformBytesBound(const Partition& p)
{
    return size_t(p.rangeCount()) * (2 * kMaxVarint + 1 + kMaxVarint);
}
size_t edgeBytesBound(int n)
{
    return size_t(4 * n) * kMaxVarint;
}
size_t correctionBytesBound(int n)
{
    return size_t(n) * n * kMaxVarint;
}

std::vector<uint8_t> serializeTransforms(const std::vector<Transform>& t, const Partition& p)
{
    std::vector<uint8_t> out;
    for (int ry = 0; ry < p.ranges_per_side; ++ry)
        for (int rx = 0; rx < p.ranges_per_side; ++rx) {
            const Transform& r = t[size_t(ry) * p.ranges_per_side + rx];
            putVarint(out, zigzag(r.domain_x - std::min(rx, p.domains_per_side - 1)));
            putVarint(out, zigzag(r.domain_y - std::min(ry, p.domains_per_side - 1)));
        }
    for (const Transform& r : t)
        out.push_back(uint8_t(int8_t(r.s)));
    int32_t previous = 0;
    for (const Transform& r : t) {
        putVarint(out, zigzag(r.o - previous));
        previous = r.o;
    }
    return out;
}

bool parseTransforms(const std::vector<uint8_t>& bytes, const Partition& p,
                     std::vector<Transform>& t)
{
    const uint8_t* at = bytes.data();
    const uint8_t* end = at + bytes.size();
    t.assign(size_t(p.rangeCount()), {});
    for (int ry = 0; ry < p.ranges_per_side; ++ry)
        for (int rx = 0; rx < p.ranges_per_side; ++rx) {
            Transform& r = t[size_t(ry) * p.ranges_per_side + rx];
            uint32_t dx = 0, dy = 0;
            if (!getVarint(at, end, dx) || !getVarint(at, end, dy))
                return false;
            r.domain_x = std::min(rx, p.domains_per_side - 1) + unzigzag(dx);
            r.domain_y = std::min(ry, p.domains_per_side - 1) + unzigzag(dy);
            if (r.domain_x < 0 || r.domain_y < 0 || r.domain_x >= p.domains_per_side ||
                r.domain_y >= p.domains_per_side)
                return false;
        }
    if (size_t(end - at) < t.size())
        return false;
    for (Transform& r : t) {
        r.s = int8_t(*at++);
        if (r.s < -fractal::kMaxScale || r.s > fractal::kMaxScale)
            return false;
    }
    int64_t o = 0;
    for (Transform& r : t) {
        uint32_t d = 0;
        if (!getVarint(at, end, d))
            return false;
        o += unzigzag(d);
        if (o < -fractal::kMaxOffset || o > fractal::kMaxOffset)
            return false;
        r.o = int32_t(o);
    }
    return at == end;
}

std::vector<uint8_t> compress(const std::vector<uint8_t>& raw)
{
    std::vector<uint8_t> out(ZSTD_compressBound(raw.size()));
    const size_t size = ZSTD_compress(out.data(), out.size(), raw.data(), raw.size(), kZstdLevel);
    if (ZSTD_isError(size))
        throw Error(std::string("fractal codec: zstd: ") + ZSTD_getErrorName(size));
    out.resize(size);
    return out;
}

// One zstd frame of exactly `size` bytes whose content is at most `limit` bytes.
int inflate(const uint8_t* src, size_t size, size_t limit, std::vector<uint8_t>& out)
{
    const size_t frame = ZSTD_findFrameCompressedSize(src, size);
    if (ZSTD_isError(frame))
        return kCodecCorrupt;
    if (frame != size)
        return kCodecTrailingBytes;
    const unsigned long long content = ZSTD_getFrameContentSize(src, size);
    if (content == ZSTD_CONTENTSIZE_UNKNOWN || content == ZSTD_CONTENTSIZE_ERROR || content > limit)
        return kCodecCorrupt;
    out.resize(size_t(content));
    const size_t got = ZSTD_decompress(out.data(), out.size(), src, size);
    if (ZSTD_isError(got) || got != out.size())
        return kCodecCorrupt;
    return kCodecOk;
}

// What a payload holds, checked: the transforms, the pinned edge values and the corrections'
// bytes.
struct Parsed {
    int iterations = 0;
    std::vector<Transform> transforms;
    std::vector<uint16_t> pinned; // n × n, edge samples only
    std::vector<uint8_t> pinned_mask;
    std::vector<uint8_t> corrections;
    std::vector<uint16_t> step_bounds; // k = 0..iterations−1; empty in a v1 payload
};

int parse(const uint8_t* src, size_t size, int n, int bound, bool paper, Parsed& out)
{
    if (size < kHeaderSize)
        return kCodecTruncated;
    if (src[0] != kMagic || (src[1] != 1 && src[1] != kPayloadVersion) || src[2] < 1 ||
        src[2] > FractalVariant::kMaxIterations || src[3] != (paper ? kPaperFlag : 0) ||
        (uint32_t(src[4]) | uint32_t(src[5]) << 8) != uint32_t(bound) || (paper && src[1] == 1))
        return kCodecBadHeader;
    out.iterations = src[2];
    const uint64_t transforms_size = getU32(src + 6), edges_size = getU32(src + 10);
    const size_t table_size = src[1] == 1 ? 0 : size_t(2) * out.iterations;
    if (kHeaderSize + table_size + transforms_size + edges_size > size)
        return kCodecTruncated;
    const Partition p = Partition::of(n);
    const uint8_t* at = src + kHeaderSize;
    out.step_bounds.clear();
    for (size_t k = 0; k < table_size; k += 2)
        out.step_bounds.push_back(uint16_t(at[k] | at[k + 1] << 8));
    at += table_size;
    std::vector<uint8_t> raw;
    if (const int s = inflate(at, size_t(transforms_size), transformBytesBound(p), raw); s)
        return s == kCodecTrailingBytes ? kCodecCorrupt : s;
    if (!parseTransforms(raw, p, out.transforms))
        return kCodecCorrupt;
    at += transforms_size;
    if (paper) { // transforms alone: nothing pinned, nothing to correct
        out.pinned.clear();
        out.pinned_mask.clear();
        out.corrections.clear();
        return edges_size == 0 && at == src + size ? kCodecOk : kCodecCorrupt;
    }
    if (const int s = inflate(at, size_t(edges_size), edgeBytesBound(n), raw); s)
        return s == kCodecTrailingBytes ? kCodecCorrupt : s;
    const int32_t step = 2 * bound + 1, top = (65535 + bound) / step;
    out.pinned.assign(size_t(n) * n, 0);
    out.pinned_mask.assign(size_t(n) * n, 0);
    const uint8_t* e = raw.data();
    const uint8_t* e_end = e + raw.size();
    int64_t q = 0;
    for (const size_t i : edgeOrder(n)) {
        uint32_t d = 0;
        if (!getVarint(e, e_end, d))
            return kCodecCorrupt;
        q += unzigzag(d);
        if (q < 0 || q > top)
            return kCodecCorrupt;
        out.pinned[i] = uint16_t(std::min<int64_t>(q * step, 65535));
        out.pinned_mask[i] = 1;
    }
    if (e != e_end)
        return kCodecCorrupt;
    at += edges_size;
    return inflate(at, size_t(src + size - at), correctionBytesBound(n), out.corrections);
}

// Adds the corrections to the attractor's interior samples. `checked`: a value the bound
// cannot explain (beyond [−E, 65535 + E]) is corruption; a partial decode (fewer iterations
// than the payload's) only clamps, as the GPU decoder does.
int correct(const std::vector<uint8_t>& bytes, int n, int bound, uint16_t* dst, bool checked = true)
{
    const int32_t step = 2 * bound + 1;
    const uint8_t* at = bytes.data();
    const uint8_t* end = at + bytes.size();
    for (int y = 1; y < n - 1; ++y)
        for (int x = 1; x < n - 1; ++x) {
            uint32_t u = 0;
            if (!getVarint(at, end, u))
                return kCodecCorrupt;
            const int64_t value = int64_t(dst[size_t(y) * n + x]) + int64_t(unzigzag(u)) * step;
            if (checked && (value < -bound || value > 65535 + bound))
                return kCodecCorrupt;
            dst[size_t(y) * n + x] = uint16_t(std::clamp<int64_t>(value, 0, 65535));
        }
    return at == end ? kCodecOk : kCodecCorrupt;
}

// The image after `iterations` of T, edges pinned unless the payload is the paper's mode.
void iterate(const Parsed& parsed, int n, int iterations, uint16_t* dst)
{
    const bool pinned = !parsed.pinned.empty();
    fractal::decodeAttractor(parsed.transforms, Partition::of(n), iterations,
                             pinned ? parsed.pinned.data() : nullptr,
                             pinned ? parsed.pinned_mask.data() : nullptr, dst);
}

} // namespace

FractalCodec::FractalCodec(double max_error, int level_count, FractalVariant variant)
    : variant_(variant)
{
    if (!(std::isfinite(max_error) && max_error >= 0 && max_error <= 32767))
        throw Error("fractal codec: the bound must be a number in [0, 32767] codes (got " +
                    std::to_string(max_error) + ")");
    if (level_count < 1 || level_count > 32)
        throw Error("fractal codec: 1 to 32 levels");
    if (variant.iterations < 1 || variant.iterations > FractalVariant::kMaxIterations)
        throw Error("fractal codec: iterations must be 1 to 32");
    if (variant.search < 0 || variant.search > FractalVariant::kMaxSearch)
        throw Error("fractal codec: search must be 0 to 1024");
    bound_ = variant.paper ? 0 : int(std::floor(max_error));
}

double FractalCodec::levelErrorBound(int) const
{
    return variant_.paper ? std::numeric_limits<double>::infinity() : double(bound_);
}

size_t FractalCodec::encodeBound(const PatchContext& ctx) const
{
    const int n = ctx.patch_size;
    return kHeaderSize + 2 * size_t(FractalVariant::kMaxIterations) +
           ZSTD_compressBound(transformBytesBound(Partition::of(n))) +
           ZSTD_compressBound(edgeBytesBound(n)) + ZSTD_compressBound(correctionBytesBound(n));
}

size_t FractalCodec::encode(uint8_t* dst, size_t dst_capacity, const uint16_t* codes,
                            const PatchContext& ctx) const
{
    const int n = ctx.patch_size;
    const Partition p = Partition::of(n);
    const std::vector<Transform> transforms = fractal::encodeTransforms(codes, p, variant_.search);

    // Edges: a function of the exact heights alone, identical in both neighbours (none in
    // the paper's mode, which sends the transforms alone).
    const bool paper = variant_.paper;
    const int32_t step = 2 * bound_ + 1;
    std::vector<uint16_t> pinned(size_t(n) * n, 0);
    std::vector<uint8_t> mask(size_t(n) * n, 0), edges;
    int32_t previous = 0;
    for (const size_t i : paper ? std::vector<size_t>() : edgeOrder(n)) {
        const int32_t q = fractal::floorDiv(int32_t(codes[i]) + bound_, step);
        putVarint(edges, zigzag(q - previous));
        previous = q;
        pinned[i] = uint16_t(std::min(q * step, 65535));
        mask[i] = 1;
    }
    // Corrections from the attractor this payload decodes to, and what stopping after k < N
    // iterations adds to the error: max |partial_k − full| (the corrections are added to every
    // iterate, so only the interior moves).
    const int iterations = variant_.iterations;
    std::vector<std::vector<uint16_t>> iterates;
    fractal::decodeIterates(
        transforms, p, iterations, paper ? nullptr : pinned.data(), paper ? nullptr : mask.data(),
        [&](int, const uint16_t* image) { iterates.emplace_back(image, image + size_t(n) * n); });
    const std::vector<uint16_t>& attractor = iterates.back();
    std::vector<uint8_t> corrections;
    std::vector<int32_t> q(size_t(n) * n, 0);
    for (int y = 1; y < n - 1 && !paper; ++y)
        for (int x = 1; x < n - 1; ++x) {
            const size_t i = size_t(y) * n + x;
            q[i] = fractal::floorDiv(int32_t(codes[i]) - attractor[i] + bound_, step);
            putVarint(corrections, zigzag(q[i]));
        }
    const auto corrected = [&](const std::vector<uint16_t>& a, size_t i) {
        return std::clamp(int64_t(a[i]) + int64_t(q[i]) * step, int64_t{0}, int64_t{65535});
    };
    std::vector<uint16_t> step_bounds(size_t(iterations), 0);
    for (int k = 0; k < iterations; ++k) {
        int64_t worst = 0;
        for (size_t i = 0; i < q.size(); ++i)
            worst = std::max(worst,
                             std::abs(corrected(iterates[size_t(k)], i) - corrected(attractor, i)));
        step_bounds[size_t(k)] = uint16_t(worst);
    }

    const std::vector<uint8_t> t = compress(serializeTransforms(transforms, p)),
                               e = paper ? std::vector<uint8_t>() : compress(edges),
                               c = paper ? std::vector<uint8_t>() : compress(corrections);
    const size_t table_size = 2 * step_bounds.size();
    const size_t total = kHeaderSize + table_size + t.size() + e.size() + c.size();
    if (total > dst_capacity)
        return 0;
    dst[0] = kMagic;
    dst[1] = kPayloadVersion;
    dst[2] = uint8_t(variant_.iterations);
    dst[3] = paper ? kPaperFlag : 0;
    putU16(dst + 4, uint32_t(bound_));
    putU32(dst + 6, uint32_t(t.size()));
    putU32(dst + 10, uint32_t(e.size()));
    uint8_t* at = dst + kHeaderSize;
    for (const uint16_t b : step_bounds) {
        putU16(at, b);
        at += 2;
    }
    for (const auto* section : {&t, &e, &c}) {
        if (section->empty())
            continue; // the paper's mode has no edges or corrections (and data() may be null)
        std::memcpy(at, section->data(), section->size());
        at += section->size();
    }
    return total;
}

int FractalCodec::decodeAttractor(uint16_t* dst, const uint8_t* src, size_t src_size,
                                  const PatchContext& ctx, int iterations) const
{
    Parsed parsed;
    if (const int status = parse(src, src_size, ctx.patch_size, bound_, variant_.paper, parsed);
        status)
        return status;
    iterate(parsed, ctx.patch_size, iterations, dst);
    return kCodecOk;
}

int FractalCodec::decode(uint16_t* dst, const uint8_t* src, size_t src_size,
                         const PatchContext& ctx) const
{
    // Every iteration the payload asks for: the full decode, corrections range-checked.
    return decodePartial(dst, src, src_size, ctx, FractalVariant::kMaxIterations);
}

int FractalCodec::decodePartial(uint16_t* dst, const uint8_t* src, size_t src_size,
                                const PatchContext& ctx, int iterations) const
{
    Parsed parsed;
    if (const int status = parse(src, src_size, ctx.patch_size, bound_, variant_.paper, parsed);
        status)
        return status;
    const int k = std::clamp(iterations, 0, parsed.iterations);
    iterate(parsed, ctx.patch_size, k, dst);
    return variant_.paper
               ? kCodecOk
               : correct(parsed.corrections, ctx.patch_size, bound_, dst, k == parsed.iterations);
}

int FractalCodec::decodeForGpu(const uint8_t* src, size_t src_size, const PatchContext& ctx,
                               std::shared_ptr<const GpuPayload>* out) const
{
    const int n = ctx.patch_size;
    Parsed parsed;
    if (const int status = parse(src, src_size, n, bound_, variant_.paper, parsed); status)
        return status;
    auto payload = std::make_shared<FractalPayload>();
    payload->iterations = parsed.iterations;
    payload->step = 2 * bound_ + 1;
    payload->pinned = !variant_.paper;
    payload->step_bounds = std::move(parsed.step_bounds);
    payload->transforms.reserve(parsed.transforms.size() * 4);
    for (const Transform& t : parsed.transforms)
        payload->transforms.insert(payload->transforms.end(), {t.domain_x, t.domain_y, t.s, t.o});
    payload->samples.assign(size_t(n) * n, 0);
    if (variant_.paper) {
        *out = std::move(payload);
        return kCodecOk;
    }
    for (size_t i = 0; i < payload->samples.size(); ++i)
        if (parsed.pinned_mask[i])
            payload->samples[i] = parsed.pinned[i];
    const uint8_t* at = parsed.corrections.data();
    const uint8_t* end = at + parsed.corrections.size();
    for (int y = 1; y < n - 1; ++y)
        for (int x = 1; x < n - 1; ++x) {
            uint32_t u = 0;
            if (!getVarint(at, end, u))
                return kCodecCorrupt;
            // A correction beyond what any 16-bit sample needs is corruption (and would
            // overflow the GPU's 32-bit arithmetic).
            const int32_t q = unzigzag(u);
            if (int64_t(std::abs(int64_t(q))) * payload->step > 65535 + 2 * int64_t(payload->step))
                return kCodecCorrupt;
            payload->samples[size_t(y) * n + x] = q;
        }
    if (at != end)
        return kCodecCorrupt;
    *out = std::move(payload);
    return kCodecOk;
}

double FractalPayload::stepBound(int steps) const
{
    if (steps >= iterations)
        return 0.0;
    if (steps < 0 || step_bounds.size() != size_t(iterations))
        return std::numeric_limits<double>::infinity(); // v1: no bound for a partial decode
    return step_bounds[size_t(steps)];
}

void FractalCodec::reconstruct(const uint16_t* codes, const PatchContext& ctx, uint16_t* out) const
{
    std::vector<uint8_t> payload(encodeBound(ctx));
    const size_t size = encode(payload.data(), payload.size(), codes, ctx);
    if (size == 0 || decode(out, payload.data(), size, ctx) != kCodecOk)
        throw Error("internal error: a fractal patch just encoded does not decode");
}

std::string FractalCodec::variantDescription() const
{
    return std::string(variant_.paper ? "the paper's (no bound), " : "bounded, ") +
           std::to_string(variant_.iterations) + " iterations, search " +
           (variant_.search == 0 ? std::string("all") : std::to_string(variant_.search));
}

void FractalCodec::storeParameters(double param[2]) const
{
    param[0] = bound_;
    param[1] = variant_.iterations;
}

} // namespace ridge
