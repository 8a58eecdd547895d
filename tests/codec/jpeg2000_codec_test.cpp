// The jpeg2000 codec (the JPEG2000 paper's model): bounds on every sample under each
// criterion and library, progressive from the reconstructed parent, identical shared edges,
// the direct fallback, and rejection of bad payloads.
#include "ridge/codec/jpeg2000_codec.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

using namespace ridge;

namespace {

constexpr int kN = 65;

std::vector<uint16_t> terrain(int n, uint32_t seed, int noise, int amplitude = 900)
{
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> jitter(-noise, noise);
    std::vector<uint16_t> v(size_t(n) * n);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
            v[size_t(y) * n + x] = uint16_t(std::clamp(
                30000 + int(amplitude * std::sin(x * 0.11 + seed) + 600 * std::cos(y * 0.07)) +
                    jitter(rng),
                0, 65535));
    return v;
}

// The child `q` of `parent_exact`'s finer grid: a 2n-1 grid sampled from one function.
std::vector<uint16_t> childOf(const std::vector<uint16_t>& fine, int n, int q)
{
    const int half = n - 1, ox = (q & 1) * half, oy = (q >> 1) * half, w = 2 * n - 1;
    std::vector<uint16_t> c(size_t(n) * n);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
            c[size_t(y) * n + x] = fine[size_t(oy + y) * w + ox + x];
    return c;
}

std::vector<uint8_t> encode(const Jpeg2000Codec& codec, const std::vector<uint16_t>& codes,
                            const PatchContext& ctx)
{
    std::vector<uint8_t> payload(codec.encodeBound(ctx));
    payload.resize(codec.encode(payload.data(), payload.size(), codes.data(), ctx));
    EXPECT_GT(payload.size(), 0u);
    return payload;
}

struct Errors {
    int max = 0;
    double rms = 0;
};

Errors errorsOver(const std::vector<uint16_t>& a, const std::vector<uint16_t>& b, int n, int w,
                  int h)
{
    Errors e;
    double squares = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const int d = std::abs(int(a[size_t(y) * n + x]) - int(b[size_t(y) * n + x]));
            e.max = std::max(e.max, d);
            squares += double(d) * d;
        }
    e.rms = std::sqrt(squares / (double(w) * h));
    return e;
}

// A parent and its four children from one fine grid: decoded top-down as a reader does,
// each child predicted from the parent's *decoded* reconstruction.
struct Family {
    std::vector<uint16_t> parent_exact, parent_decoded;
    std::vector<uint16_t> child_exact[4], child_decoded[4];
    std::vector<uint8_t> child_payload[4];
};

Family codeFamily(const Jpeg2000Codec& codec, uint32_t seed, int noise, int amplitude = 900)
{
    const int w = 2 * kN - 1;
    const std::vector<uint16_t> fine = terrain(w, seed, noise, amplitude);
    Family f;
    f.parent_exact.resize(size_t(kN) * kN);
    for (int y = 0; y < kN; ++y)
        for (int x = 0; x < kN; ++x)
            f.parent_exact[size_t(y) * kN + x] = fine[size_t(2 * y) * w + 2 * x];
    const PatchContext root{kN, 0, nullptr, 0, 0, 0};
    const std::vector<uint8_t> rp = encode(codec, f.parent_exact, root);
    f.parent_decoded.resize(f.parent_exact.size());
    EXPECT_EQ(codec.decode(f.parent_decoded.data(), rp.data(), rp.size(), root), kCodecOk);
    for (int q = 0; q < 4; ++q) {
        f.child_exact[q] = childOf(fine, kN, q);
        const PatchContext ctx{kN, 1, f.parent_decoded.data(), q, 0, 0};
        f.child_payload[q] = encode(codec, f.child_exact[q], ctx);
        f.child_decoded[q].resize(f.child_exact[q].size());
        EXPECT_EQ(codec.decode(f.child_decoded[q].data(), f.child_payload[q].data(),
                               f.child_payload[q].size(), ctx),
                  kCodecOk);
    }
    return f;
}

} // namespace

TEST(Jpeg2000Variant, BitsAndNamesRoundTrip)
{
    for (int bits = 0; bits < 16; ++bits) {
        const auto v = Jpeg2000Variant::fromBits(bits);
        if (((bits >> 1) & 3) == 3) {
            EXPECT_FALSE(v) << bits;
            continue;
        }
        ASSERT_TRUE(v) << bits;
        EXPECT_EQ(v->bits(), bits);
    }
    EXPECT_FALSE(Jpeg2000Variant::fromBits(16));
    EXPECT_FALSE(Jpeg2000Variant::fromBits(-1));
    const auto v =
        Jpeg2000Variant::fromName("jpeg2000,encoding=direct,criterion=rms,library=htj2k");
    ASSERT_TRUE(v);
    EXPECT_EQ(v->encoding, Jpeg2000Encoding::Direct);
    EXPECT_EQ(v->criterion, CompressionCriterion::Rms);
    EXPECT_EQ(v->library, Jpeg2000Library::Htj2k);
    EXPECT_EQ(Jpeg2000Variant::fromName("jpeg2000")->bits(), 0);
    for (const char* bad :
         {"jpeg2000,", "jpeg2000,criterion=mse", "jpeg2000x", "jpeg2000,library="})
        EXPECT_FALSE(Jpeg2000Variant::fromName(bad)) << bad;
    EXPECT_EQ(*codecIdOf("jpeg2000,criterion=lossless"), kJpeg2000CodecId);
    EXPECT_TRUE(isLossyCodec("jpeg2000"));
}

TEST(Jpeg2000Codec, StoredParametersAreValidated)
{
    const Jpeg2000Codec codec(3, 5, *Jpeg2000Variant::fromName("jpeg2000,criterion=rms"));
    CodecSettings s;
    s.level_count = 5;
    codec.storeParameters(s.param);
    const auto back = makeCodec(kJpeg2000CodecId, s);
    ASSERT_TRUE(back);
    EXPECT_EQ(back->levelErrorBound(2), 3 * Jpeg2000Variant::kRmsGuardFactor);
    std::string problem;
    for (double bits : {6.0, 16.0, 1.5, -1.0}) {
        CodecSettings bad = s;
        bad.param[1] = bits;
        EXPECT_EQ(makeCodec(kJpeg2000CodecId, bad, &problem), nullptr) << bits;
        EXPECT_NE(problem.find("codec_param[1]"), std::string::npos) << problem;
    }
    for (double e : {0.0, -1.0, 40000.0, double(NAN)}) {
        CodecSettings bad = s;
        bad.param[0] = e;
        EXPECT_EQ(makeCodec(kJpeg2000CodecId, bad, &problem), nullptr) << e;
        EXPECT_NE(problem.find("codec_param[0]"), std::string::npos) << problem;
    }
    CodecSettings lossless = s;
    lossless.param[0] = 0;
    lossless.param[1] = Jpeg2000Variant::fromName("jpeg2000,criterion=lossless")->bits();
    EXPECT_NE(makeCodec(kJpeg2000CodecId, lossless), nullptr); // E = 0 is exact, allowed
    CodecSettings tables = s;
    tables.tables = {1, 2, 3};
    EXPECT_EQ(makeCodec(kJpeg2000CodecId, tables, &problem), nullptr);
}

TEST(Jpeg2000Codec, Htj2kPayloadsAreDecodedOnlyWhenAllowed)
{
    // OpenJPH 0.9 aborts on some malformed codestreams (fuzz_jpeg2000_decode found two), so
    // HTJ2K is read only when the user vouches for the archive.
    unsetenv("RIDGE_ALLOW_HTJ2K");
    const Jpeg2000Codec codec(2, 1, *Jpeg2000Variant::fromName("jpeg2000,library=htj2k"));
    const std::vector<uint16_t> codes = terrain(kN, 9, 4);
    const PatchContext root{kN, 0, nullptr, 0, 0, 0};
    const std::vector<uint8_t> payload = encode(codec, codes, root); // its own decode is trusted
    std::vector<uint16_t> out(codes.size());
    EXPECT_EQ(codec.decode(out.data(), payload.data(), payload.size(), root), kCodecDisabled);
    setenv("RIDGE_ALLOW_HTJ2K", "1", 1);
    EXPECT_EQ(codec.decode(out.data(), payload.data(), payload.size(), root), kCodecOk);
}

TEST(Jpeg2000Codec, MaxAbsBoundHoldsOnEverySampleForEachLibraryAndEncoding)
{
    setenv("RIDGE_ALLOW_HTJ2K", "1", 1);
    for (const char* name : {"jpeg2000", "jpeg2000,library=htj2k", "jpeg2000,encoding=direct",
                             "jpeg2000,criterion=lossless"})
        for (int e : {1, 3, 12}) {
            const Jpeg2000Codec codec(e, 2, *Jpeg2000Variant::fromName(name));
            const Family f = codeFamily(codec, 7 + e, 6);
            EXPECT_LE(errorsOver(f.parent_exact, f.parent_decoded, kN, kN, kN).max, e) << name;
            for (int q = 0; q < 4; ++q) {
                const Errors err = errorsOver(f.child_exact[q], f.child_decoded[q], kN, kN, kN);
                EXPECT_LE(err.max, e) << name << " e " << e << " child " << q;
                // decode(encode(x)) is what reconstruct() promises the build.
                std::vector<uint16_t> again(f.child_exact[q].size());
                codec.reconstruct(f.child_exact[q].data(),
                                  {kN, 1, f.parent_decoded.data(), q, 0, 0}, again.data());
                EXPECT_EQ(again, f.child_decoded[q]) << name;
                const bool direct = std::string(name).find("direct") != std::string::npos;
                EXPECT_EQ(f.child_payload[q][2], direct ? 1 : 0) << name; // kind
            }
        }
}

TEST(Jpeg2000Codec, ProgressiveCodesFewerBytesThanDirect)
{
    // The paper's Tables 1-2 in miniature: prediction from the parent pays.
    size_t bytes[2] = {0, 0};
    for (int direct = 0; direct < 2; ++direct) {
        const Jpeg2000Codec codec(
            2, 2, *Jpeg2000Variant::fromName(direct ? "jpeg2000,encoding=direct" : "jpeg2000"));
        const Family f = codeFamily(codec, 3, 3);
        for (int q = 0; q < 4; ++q)
            bytes[direct] += f.child_payload[q].size();
    }
    EXPECT_LT(bytes[0], bytes[1]);
}

TEST(Jpeg2000Codec, RmsCriterionHoldsWithItsMaxGuard)
{
    const double E = 4;
    const Jpeg2000Codec codec(E, 2, *Jpeg2000Variant::fromName("jpeg2000,criterion=rms"));
    const Family f = codeFamily(codec, 11, 10);
    for (int q = 0; q < 4; ++q) {
        const Errors err = errorsOver(f.child_exact[q], f.child_decoded[q], kN, kN, kN);
        EXPECT_LE(err.rms, E);
        EXPECT_LE(err.max, E * Jpeg2000Variant::kRmsGuardFactor);
    }
    // The RMS criterion compresses more than max-abs at the same E (Table 5's shape).
    const Jpeg2000Codec strict(E, 2);
    const Family g = codeFamily(strict, 11, 10);
    size_t rms_bytes = 0, max_bytes = 0;
    for (int q = 0; q < 4; ++q) {
        rms_bytes += f.child_payload[q].size();
        max_bytes += g.child_payload[q].size();
    }
    EXPECT_LT(rms_bytes, max_bytes);
}

TEST(Jpeg2000Codec, SiblingsReconstructIdenticalSharedEdges)
{
    for (const char* name : {"jpeg2000", "jpeg2000,encoding=direct", "jpeg2000,criterion=rms"}) {
        const Jpeg2000Codec codec(3, 2, *Jpeg2000Variant::fromName(name));
        const Family f = codeFamily(codec, 5, 20);
        for (int y = 0; y < kN; ++y) {
            // child 0's right column is child 1's left column, child 2's of child 3's.
            EXPECT_EQ(f.child_decoded[0][size_t(y) * kN + kN - 1],
                      f.child_decoded[1][size_t(y) * kN])
                << name << " row " << y;
            EXPECT_EQ(f.child_decoded[2][size_t(y) * kN + kN - 1],
                      f.child_decoded[3][size_t(y) * kN])
                << name;
        }
        for (int x = 0; x < kN; ++x)
            EXPECT_EQ(f.child_decoded[0][size_t(kN - 1) * kN + x], f.child_decoded[2][x]) << name;
    }
}

TEST(Jpeg2000Codec, ClippedRegionRepeatsItsLastCodedSamples)
{
    const Jpeg2000Codec codec(2, 1);
    const std::vector<uint16_t> codes = terrain(kN, 9, 4);
    const PatchContext ctx{kN, 0, nullptr, 0, 20, 33};
    const std::vector<uint8_t> payload = encode(codec, codes, ctx);
    std::vector<uint16_t> out(codes.size());
    ASSERT_EQ(codec.decode(out.data(), payload.data(), payload.size(), ctx), kCodecOk);
    EXPECT_LE(errorsOver(codes, out, kN, 20, 33).max, 2);
    for (int y = 0; y < kN; ++y)
        for (int x = 0; x < kN; ++x)
            EXPECT_EQ(out[size_t(y) * kN + x], out[size_t(std::min(y, 32)) * kN + std::min(x, 19)]);
}

TEST(Jpeg2000Codec, DifferenceTooWideForSixteenBitsFallsBackToDirect)
{
    // E = 0 (exact) and a parent reconstruction far from the child: D spans more than
    // 2^16 - 1 whole steps, so the patch is coded directly, still exact.
    const Jpeg2000Codec codec(0, 2, *Jpeg2000Variant::fromName("jpeg2000,criterion=lossless"));
    // Parent columns alternate 0 / 65535; the child's even columns invert them, so D
    // spans [-65535, 65535].
    std::vector<uint16_t> parent(size_t(kN) * kN), child = terrain(kN, 1, 0);
    for (int y = 0; y < kN; ++y)
        for (int x = 0; x < kN; ++x) {
            parent[size_t(y) * kN + x] = (x & 1) ? 65535 : 0;
            if (x % 2 == 0)
                child[size_t(y) * kN + x] = ((x / 2) & 1) ? 0 : 65535;
        }
    const PatchContext ctx{kN, 1, parent.data(), 0, 0, 0};
    const std::vector<uint8_t> payload = encode(codec, child, ctx);
    EXPECT_EQ(payload[2], 1); // direct
    std::vector<uint16_t> out(child.size());
    ASSERT_EQ(codec.decode(out.data(), payload.data(), payload.size(), ctx), kCodecOk);
    EXPECT_EQ(out, child);
}

TEST(Jpeg2000Codec, WideDifferenceTakesMoreBitsToHoldTheBound)
{
    // A 1-code bound over a D range of ~20000 codes: 8 bits would step by 80.
    const Jpeg2000Codec codec(1, 2);
    std::vector<uint16_t> parent(size_t(kN) * kN, 30000), child = terrain(kN, 4, 0, 9000);
    const PatchContext ctx{kN, 1, parent.data(), 3, 0, 0};
    const std::vector<uint8_t> payload = encode(codec, child, ctx);
    EXPECT_GT(payload[3], 8); // bits
    std::vector<uint16_t> out(child.size());
    ASSERT_EQ(codec.decode(out.data(), payload.data(), payload.size(), ctx), kCodecOk);
    EXPECT_LE(errorsOver(child, out, kN, kN, kN).max, 1);
}

TEST(Jpeg2000Codec, DifferencePlusPredictionIsTheDecode)
{
    // What a GPU pass computes (§4): the decoded D̂, scaled, added to the prediction.
    const Jpeg2000Codec codec(2, 2);
    const Family f = codeFamily(codec, 21, 5);
    for (int q = 0; q < 4; ++q) {
        const PatchContext ctx{kN, 1, f.parent_decoded.data(), q, 0, 0};
        Jpeg2000Difference d;
        ASSERT_EQ(
            codec.decodeDifference(f.child_payload[q].data(), f.child_payload[q].size(), ctx, &d),
            kCodecOk);
        EXPECT_EQ(d.bits, 8);
        std::vector<uint16_t> out(size_t(kN) * kN);
        Jpeg2000Codec::addPrediction(d, ctx, out.data());
        EXPECT_EQ(out, f.child_decoded[q]);
    }
}

// What a streamer does for a parent it delivered to the GPU when a child needs its codes:
// finishOnCpu(decodeForGpu(payload)) == decode(payload), without decoding the codestream
// again; a payload that is not the patch's is refused.
TEST(Jpeg2000Codec, FinishOnCpuTurnsTheGpuPayloadIntoDecodesCodes)
{
    const Jpeg2000Codec codec(2, 2);
    ASSERT_TRUE(codec.capabilities().gpu.finishes_on_cpu);
    const Family f = codeFamily(codec, 21, 5);
    for (int q = 0; q < 4; ++q) {
        const PatchContext ctx{kN, 1, f.parent_decoded.data(), q, 0, 0};
        std::shared_ptr<const GpuPayload> payload;
        ASSERT_EQ(
            codec.decodeForGpu(f.child_payload[q].data(), f.child_payload[q].size(), ctx, &payload),
            kCodecOk);
        std::vector<uint16_t> out(size_t(kN) * kN);
        ASSERT_EQ(codec.finishOnCpu(*payload, ctx, out.data()), kCodecOk);
        EXPECT_EQ(out, f.child_decoded[q]);

        const auto& d = dynamic_cast<const Jpeg2000Difference&>(*payload);
        EXPECT_EQ(codec.finishOnCpu(*payload, {kN, 1, nullptr, q, 0, 0}, out.data()),
                  d.kind == Jpeg2000Encoding::Progressive ? kCodecNeedsParent : kCodecOk);
        EXPECT_EQ(codec.finishOnCpu(*payload, {kN, 0, nullptr, 0, 0, 0}, out.data()),
                  d.kind == Jpeg2000Encoding::Progressive ? kCodecBadHeader : kCodecOk)
            << "the root has no parent to add to";
        EXPECT_EQ(
            codec.finishOnCpu(*payload, {kN, 1, f.parent_decoded.data(), q, 33, 0}, out.data()),
            kCodecBadHeader)
            << "another coded region";
        Jpeg2000Difference short_edge = d;
        short_edge.right.pop_back();
        EXPECT_EQ(codec.finishOnCpu(short_edge, ctx, out.data()), kCodecBadHeader);
        Jpeg2000Difference short_image = d;
        short_image.image.pop_back();
        EXPECT_EQ(codec.finishOnCpu(short_image, ctx, out.data()), kCodecBadHeader);
    }
}

TEST(Jpeg2000Codec, BadPayloadsAreRejected)
{
    const Jpeg2000Codec codec(2, 2);
    const Family f = codeFamily(codec, 2, 5);
    const std::vector<uint8_t>& good = f.child_payload[1];
    const PatchContext ctx{kN, 1, f.parent_decoded.data(), 1, 0, 0};
    std::vector<uint16_t> out(size_t(kN) * kN);
    // Every truncation fails (strict OpenJPEG decoding: no blurrier picture).
    for (size_t n = 0; n < good.size(); ++n)
        EXPECT_LT(codec.decode(out.data(), good.data(), n, ctx), 0) << n;
    const auto with = [&](size_t at, uint8_t value) {
        std::vector<uint8_t> p = good;
        p[at] = value;
        return codec.decode(out.data(), p.data(), p.size(), ctx);
    };
    EXPECT_EQ(with(0, 'P'), kCodecBadHeader); // magic
    EXPECT_EQ(with(1, 2), kCodecBadHeader);   // payload version
    EXPECT_EQ(with(2, 2), kCodecBadHeader);   // kind
    EXPECT_EQ(with(3, 0), kCodecBadHeader);   // bits
    EXPECT_EQ(with(3, 17), kCodecBadHeader);
    EXPECT_EQ(with(4, 2), kCodecBadHeader);     // unknown flag
    EXPECT_LT(with(3, 9), 0);                   // bits disagree with the codestream
    EXPECT_EQ(with(9, 0), kCodecBadHeader);     // step 0 (with bytes 10..12 zero)
    EXPECT_EQ(with(12, 0x40), kCodecBadHeader); // step far beyond any range
    EXPECT_EQ(with(16, 0x7f), kCodecTruncated); // border_bytes beyond the payload
    // The root cannot be a difference layer (it has no parent).
    std::vector<uint8_t> root = good;
    EXPECT_EQ(codec.decode(out.data(), root.data(), root.size(), {kN, 0, nullptr, 0, 0, 0}),
              kCodecBadHeader);
    // A difference patch decoded without its parent.
    EXPECT_EQ(codec.decode(out.data(), good.data(), good.size(), {kN, 1, nullptr, 1, 0, 0}),
              kCodecNeedsParent);
    // Random damage anywhere never crashes, and never decodes out of the code range.
    std::mt19937 rng(3);
    for (int trial = 0; trial < 300; ++trial) {
        std::vector<uint8_t> p = good;
        for (int k = 0; k < 3; ++k)
            p[rng() % p.size()] ^= uint8_t(1 + rng() % 255);
        (void)codec.decode(out.data(), p.data(), p.size(), ctx);
    }
}
