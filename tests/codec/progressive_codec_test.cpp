// The progressive codec's parts: range coder, level quantizer, reconstruction, payloads.
#include "ridge/codec/level_quantizer.h"
#include "ridge/codec/progressive_codec.h"
#include "ridge/codec/range_coder.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

using namespace ridge;

namespace {

// Terrain-like patch: smooth relief plus noise, so residuals span small and large values.
std::vector<uint16_t> terrainPatch(int n, uint32_t seed, int noise, int base = 30000)
{
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> jitter(-noise, noise);
    std::vector<uint16_t> v(static_cast<size_t>(n) * n);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
            v[y * n + x] = static_cast<uint16_t>(
                std::clamp(base + int(900 * std::sin(x * 0.07 + seed) + 600 * std::cos(y * 0.05)) +
                               jitter(rng),
                           0, 65535));
    return v;
}

template <int N> void roundTripSymbols(uint32_t seed, double skew)
{
    std::mt19937 rng(seed);
    std::geometric_distribution<int> geo(skew);
    std::uniform_int_distribution<uint32_t> bits(0, (1u << 20) - 1);
    std::vector<int> symbols(20000);
    std::vector<uint32_t> raw(symbols.size());
    for (size_t i = 0; i < symbols.size(); ++i) {
        symbols[i] = std::min(geo(rng), N - 1);
        raw[i] = bits(rng) >> (i % 20);
    }
    std::vector<uint8_t> stream;
    {
        rc::Encoder enc(stream);
        rc::AdaptiveCdf<N> model;
        for (size_t i = 0; i < symbols.size(); ++i) {
            enc.encode(model, symbols[i]);
            if (i % 7 == 0)
                enc.encodeBits(raw[i], 20 - int(i % 20));
        }
        enc.finish();
    }
    rc::Decoder dec(stream.data(), stream.size());
    rc::AdaptiveCdf<N> model;
    for (size_t i = 0; i < symbols.size(); ++i) {
        ASSERT_EQ(dec.decode(model), symbols[i]) << "symbol " << i;
        if (i % 7 == 0) {
            ASSERT_EQ(dec.decodeBits(20 - int(i % 20)), raw[i]) << "bits " << i;
        }
    }
    EXPECT_TRUE(dec.ok());
    EXPECT_EQ(dec.remaining(), 0u); // the decoder reads exactly what the encoder wrote
}

// Every payload format's variants: v1's four (the paper's and ridge's first among them), and
// v2, v3 and v4 with each bound schedule (v1's, the hybrid, all nested) and both predictors.
std::vector<ProgressiveVariant> allVariants()
{
    std::vector<ProgressiveVariant> v;
    for (int bits = 0; bits < 8; bits += 2)
        v.push_back(*ProgressiveVariant::fromBits(bits));
    for (const int format : {2, 3, 4})
        for (const int nested : {1, 2, 32})
            for (const OddPredictor p : {OddPredictor::Bilinear, OddPredictor::Cubic})
                v.push_back({p, true, format, nested});
    return v;
}

} // namespace

TEST(RangeCoder, RoundTripsRandomSymbolStreamsExactly)
{
    for (uint32_t seed = 1; seed <= 5; ++seed) {
        roundTripSymbols<2>(seed, 0.7);
        roundTripSymbols<3>(seed, 0.3);
        roundTripSymbols<4>(seed, 0.5);
        roundTripSymbols<16>(seed, 0.2);
        roundTripSymbols<16>(seed, 0.95); // very skewed: probabilities at the frequency floor
        roundTripSymbols<16>(seed, 0.01); // near uniform over the alphabet
    }
}

TEST(RangeCoder, AdaptationCompressesASkewedSource)
{
    std::vector<uint8_t> stream;
    rc::Encoder enc(stream);
    rc::AdaptiveCdf<16> model;
    for (int i = 0; i < 10000; ++i)
        enc.encode(model, i % 50 == 0 ? 5 : 0);
    enc.finish();
    // Entropy of p = 0.02 is 0.14 bits/symbol: 10000 symbols must take well under 400 bytes.
    EXPECT_LT(stream.size(), 400u);
}

TEST(RangeCoder, TruncatedStreamIsDetected)
{
    std::vector<uint8_t> stream;
    {
        rc::Encoder enc(stream);
        rc::AdaptiveCdf<16> model;
        for (int i = 0; i < 5000; ++i)
            enc.encode(model, i % 13);
        enc.finish();
    }
    rc::Decoder dec(stream.data(), stream.size() / 2);
    rc::AdaptiveCdf<16> model;
    for (int i = 0; i < 5000; ++i)
        dec.decode(model);
    EXPECT_FALSE(dec.ok());
    EXPECT_TRUE(dec.truncated());
}

TEST(LevelQuantizer, EveryCodeWithinThePapersLevelBoundAndRefinementsStaySmall)
{
    for (const double e : {0.0, 0.4, 1.0, 2.5, 7.0, 100.0}) {
        for (int k = 0; k <= 6; ++k) {
            const LevelQuantizer q = LevelQuantizer::make(e, k);
            const LevelQuantizer coarser = LevelQuantizer::make(e, k + 1);
            // δ_l = δ_l0 · 2^k exactly as the paper, floored to integer codes.
            EXPECT_EQ(q.bound, static_cast<int>(std::floor(e * (1 << k))));
            int64_t large_refinements = 0;
            for (int h = 0; h <= 65535; ++h) {
                const int32_t bin = q.quantize(static_cast<uint16_t>(h));
                ASSERT_LE(std::abs(int(q.reconstruct(bin)) - h), q.bound)
                    << "e " << e << " k " << k << " h " << h;
                // The refinement against the parent's reconstruction, requantized.
                const uint16_t parent =
                    coarser.reconstruct(coarser.quantize(static_cast<uint16_t>(h)));
                const int32_t r = bin - q.quantize(parent);
                ASSERT_LE(std::abs(r), 2) << h;
                large_refinements += std::abs(r) == 2;
            }
            EXPECT_LT(large_refinements, 65536 / 50) << "e " << e << " k " << k;
        }
    }
}

TEST(ProgressiveCodec, DecodesWhatReconstructPredictsForEveryVariantAndQuadrant)
{
    for (const ProgressiveVariant& variant : allVariants()) {
        for (const int e : {0, 1, 3, 20}) {
            const ProgressiveCodec codec(e, 4, variant);
            for (const int n : {5, 17, 65}) {
                // Root (level 0) and a chain: level 1 child of the root's reconstruction.
                const std::vector<uint16_t> root = terrainPatch(n, 7, 40);
                std::vector<uint16_t> root_drawn(root.size()), decoded(root.size());
                codec.reconstruct(root.data(), {n, 0, nullptr, 0}, root_drawn.data());
                std::vector<uint8_t> payload(codec.encodeBound({n, 0, nullptr, 0}));
                payload.resize(
                    codec.encode(payload.data(), payload.size(), root.data(), {n, 0, nullptr, 0}));
                ASSERT_GT(payload.size(), 0u);
                ASSERT_EQ(codec.decode(decoded.data(), payload.data(), payload.size(),
                                       {n, 0, nullptr, 0}),
                          kCodecOk);
                ASSERT_EQ(decoded, root_drawn) << variant.describe();
                for (int child = 0; child < 4; ++child) {
                    const std::vector<uint16_t> codes = terrainPatch(n, 11 + child, 25);
                    const PatchContext ctx{n, 1, root_drawn.data(), child};
                    std::vector<uint16_t> expected(codes.size());
                    codec.reconstruct(codes.data(), ctx, expected.data());
                    for (size_t i = 0; i < codes.size(); ++i)
                        ASSERT_LE(std::abs(int(expected[i]) - int(codes[i])),
                                  codec.levelErrorBound(1));
                    payload.assign(codec.encodeBound(ctx), 0);
                    payload.resize(codec.encode(payload.data(), payload.size(), codes.data(), ctx));
                    ASSERT_GT(payload.size(), 0u);
                    ASSERT_EQ(codec.decode(decoded.data(), payload.data(), payload.size(), ctx),
                              kCodecOk);
                    ASSERT_EQ(decoded, expected)
                        << variant.describe() << " n " << n << " child " << child;
                }
            }
        }
    }
}

TEST(ProgressiveCodec, CodesExtremeAndUnrelatedParentsThroughTheEscapes)
{
    // A parent unrelated to the child (Neville levels, clamped padding) and codes at both
    // ends of the range: refinements and residuals leave the small alphabets.
    const int n = 33;
    const ProgressiveCodec codec(0, 3);
    std::vector<uint16_t> parent(n * n), codes(n * n), decoded(n * n);
    std::mt19937 rng(3);
    for (size_t i = 0; i < codes.size(); ++i) {
        parent[i] = static_cast<uint16_t>(rng());
        codes[i] = (i % 3 == 0) ? 0 : (i % 3 == 1 ? 65535 : static_cast<uint16_t>(rng()));
    }
    const PatchContext ctx{n, 2, parent.data(), 3};
    std::vector<uint8_t> payload(codec.encodeBound(ctx));
    payload.resize(codec.encode(payload.data(), payload.size(), codes.data(), ctx));
    ASSERT_GT(payload.size(), 0u);
    ASSERT_EQ(codec.decode(decoded.data(), payload.data(), payload.size(), ctx), kCodecOk);
    EXPECT_EQ(decoded, codes); // e = 0 at the finest level: exact
}

void rejectsTruncatedCorruptAndParentlessPayloads(const ProgressiveVariant& variant);

TEST(ProgressiveCodec, RejectsTruncatedCorruptAndParentlessPayloads)
{
    for (const ProgressiveVariant& variant :
         {ProgressiveVariant::v2(), ProgressiveVariant::v3(), ProgressiveVariant{}}) {
        SCOPED_TRACE(variant.describe());
        rejectsTruncatedCorruptAndParentlessPayloads(variant);
    }
}

TEST(ProgressiveCodec, PayloadVersionsAreNotInterchangeable)
{
    // A payload of v2, v3 or v4 is refused by a codec of another of them (its version byte),
    // even though they share the stream's layout: the contexts differ.
    const int n = 33;
    const ProgressiveCodec v2(1, 2, ProgressiveVariant::v2()), v3(1, 2, ProgressiveVariant::v3()),
        v4(1, 2);
    const std::vector<uint16_t> root = terrainPatch(n, 4, 5);
    std::vector<uint16_t> out(root.size());
    const PatchContext ctx{n, 0, nullptr, 0};
    for (const ProgressiveCodec* from : {&v2, &v3, &v4}) {
        std::vector<uint8_t> payload(from->encodeBound(ctx));
        payload.resize(from->encode(payload.data(), payload.size(), root.data(), ctx));
        ASSERT_EQ(payload[1], from->variant().format);
        for (const ProgressiveCodec* other : {&v2, &v3, &v4}) {
            if (other != from) {
                EXPECT_EQ(other->decode(out.data(), payload.data(), payload.size(), ctx),
                          kCodecBadHeader);
            }
        }
    }
}

// The decoder's planar cubic passes (progressive_reconstruction.cpp) against predictOdd, the
// encoder's, in pass order, on residuals no encoder would write: large, of both signs, over
// regions of every parity and with corrections of any weights.
TEST(ProgressiveReconstruction, PlanarPassesEqualPredictOddOnAnyResiduals)
{
    std::mt19937 rng(9);
    for (const int n : {5, 9, 17, 33, 65}) {
        for (const auto& [w, h] : {std::pair{n, n}, std::pair{3, 3}, std::pair{5, n},
                                   std::pair{n, 7}, std::pair{(n / 2) | 1, (n / 3) | 1}}) {
            if (w < 3 || h < 3 || w > n || h > n)
                continue;
            const CodedRegion region{w, h};
            std::vector<int32_t> parent(size_t(n) * n), residuals(parent.size());
            for (int32_t& v : parent)
                v = int32_t(rng() % 4000);
            for (int32_t& v : residuals)
                v = rng() % 4 == 0 ? int32_t(rng() % 60001) - 30000 : int32_t(rng() % 5) - 2;
            PredictorWeights weights;
            for (auto& c : weights.w)
                for (int16_t& x : c)
                    x = int16_t(int(rng() % 8191) - 4095);
            const PredictorWeights* const none = nullptr;
            for (const PredictorWeights* wp :
                 {none, static_cast<const PredictorWeights*>(&weights)}) {
                for (int child = 0; child < 4; ++child) {
                    std::vector<int32_t> planar(parent.size(), 0), reference(parent.size(), 0);
                    reconstructChild(residuals.data(), parent.data(), child, n, region,
                                     OddPredictor::Cubic, planar.data(), wp);
                    const int half = (n - 1) / 2;
                    for (int y = 0; y < h; y += 2)
                        for (int x = 0; x < w; x += 2)
                            reference[size_t(y) * n + x] =
                                parent[size_t((child >> 1) * half + y / 2) * n +
                                       (child & 1) * half + x / 2] +
                                residuals[size_t(y) * n + x];
                    for (const int pass : {1, 2, 3})
                        for (int y = pass >> 1; y < h; y += 2)
                            for (int x = pass & 1; x < w; x += 2) {
                                const size_t i = size_t(y) * n + x;
                                reference[i] = predictOdd(reference.data(), n, region, x, y,
                                                          OddPredictor::Cubic, wp) -
                                               residuals[i];
                            }
                    ASSERT_EQ(planar, reference)
                        << "n " << n << ", region " << w << "x" << h << ", child " << child
                        << (wp ? ", corrected" : "");
                }
            }
        }
    }
}

void rejectsTruncatedCorruptAndParentlessPayloads(const ProgressiveVariant& variant)
{
    const int n = 65;
    const ProgressiveCodec codec(1, 2, variant);
    const std::vector<uint16_t> parent = terrainPatch(n, 1, 10), codes = terrainPatch(n, 2, 30);
    std::vector<uint16_t> parent_drawn(parent.size()), out(codes.size());
    codec.reconstruct(parent.data(), {n, 0, nullptr, 0}, parent_drawn.data());
    const PatchContext ctx{n, 1, parent_drawn.data(), 2};
    std::vector<uint8_t> payload(codec.encodeBound(ctx));
    payload.resize(codec.encode(payload.data(), payload.size(), codes.data(), ctx));

    EXPECT_EQ(codec.decode(out.data(), payload.data(), payload.size(), {n, 1, nullptr, 2}),
              kCodecNeedsParent);
    for (size_t size = 0; size < payload.size(); size += 1 + size / 8)
        EXPECT_LT(codec.decode(out.data(), payload.data(), size, ctx), 0)
            << "truncated to " << size;
    std::vector<uint8_t> longer = payload;
    longer.push_back(0x5a);
    EXPECT_EQ(codec.decode(out.data(), longer.data(), longer.size(), ctx), kCodecTrailingBytes);
    std::vector<uint8_t> bad = payload;
    bad[0] = 'X';
    EXPECT_EQ(codec.decode(out.data(), bad.data(), bad.size(), ctx), kCodecBadHeader);
    // Bit flips anywhere: an error or some decoded patch, always promptly and in bounds
    // (ASan/UBSan runs make out-of-bounds or overflow a failure).
    int rejected = 0;
    for (size_t i = 2; i < payload.size(); i += 3) {
        bad = payload;
        bad[i] ^= static_cast<uint8_t>(1u << (i % 8));
        rejected += codec.decode(out.data(), bad.data(), bad.size(), ctx) < 0;
    }
    EXPECT_GT(rejected, 0);
}

TEST(ProgressiveCodec, SettingsRoundTripThroughTheArchiveHeaderParameters)
{
    for (const ProgressiveVariant& variant : allVariants()) {
        const ProgressiveCodec codec(5, 7, variant);
        CodecSettings settings;
        settings.level_count = 7;
        codec.storeParameters(settings.param);
        const std::unique_ptr<HeightCodec> back = makeCodec(kProgressiveCodecId, settings);
        ASSERT_NE(back, nullptr) << variant.describe();
        for (int level = 0; level < 7; ++level)
            EXPECT_EQ(back->levelErrorBound(level), codec.levelErrorBound(level));
        EXPECT_EQ(static_cast<const ProgressiveCodec&>(*back).variant().bits(), variant.bits());
    }
    CodecSettings settings;
    settings.level_count = 7;
    settings.param[0] = 5;
    for (const double bits :
         {1.0, 16.0 + 2, 8.0, 8.0 + 33 * 16, 2.5, -8.0, 1024.0, 1024.0 + 8, 1024.0 + 16 + 2,
          2048.0 + 16, 2048.0 + 8, 3072.0 + 8 + 16, 4096.0 + 8 + 16}) {
        // reserved bit, v1 with nested levels, v2 with 0 or 33, v3 without v2's bit or with 0
        // nested levels, v4 without v2's bit or with 0 nested levels, v3 and v4 at once, bits
        // past v4's
        settings.param[1] = bits;
        EXPECT_EQ(makeCodec(kProgressiveCodecId, settings), nullptr) << bits;
    }
    // The nested schedule: the finest K levels at δ_l0, doubling above.
    const ProgressiveCodec hybrid(3, 6, {OddPredictor::Cubic, true, 2, 2});
    for (int level = 0; level < 6; ++level)
        EXPECT_EQ(hybrid.levelErrorBound(level), level >= 4 ? 3 : 3 << (4 - level)) << level;
    settings.param[1] = 1; // reserved variant bit
    EXPECT_EQ(makeCodec(kProgressiveCodecId, settings), nullptr);
    settings.param[1] = 6;
    settings.param[0] = -1;
    EXPECT_EQ(makeCodec(kProgressiveCodecId, settings), nullptr);
}

TEST(ProgressiveCodec, DecodeResidualsIsTheCpuHalfOfDecodeAndRejectsBadPayloads)
{
    // decodeResiduals + reconstructChild over the requantized parent == decode: the split the
    // GPU decoder (render/gpu_progressive_decoder) relies on.
    const int n = 33;
    for (const ProgressiveVariant& variant : allVariants()) {
        const ProgressiveCodec codec(2, 3, variant);
        const std::vector<uint16_t> parent = terrainPatch(n, 5, 30), codes = terrainPatch(n, 6, 20);
        std::vector<uint16_t> parent_drawn(parent.size()), decoded(codes.size());
        codec.reconstruct(parent.data(), {n, 0, nullptr, 0}, parent_drawn.data());
        const PatchContext ctx{n, 2, parent_drawn.data(), 1};
        std::vector<uint8_t> payload(codec.encodeBound(ctx));
        payload.resize(codec.encode(payload.data(), payload.size(), codes.data(), ctx));
        ASSERT_EQ(codec.decode(decoded.data(), payload.data(), payload.size(), ctx), kCodecOk);

        std::vector<int32_t> residuals(codes.size()), base(codes.size()), q(codes.size());
        ASSERT_EQ(codec.decodeResiduals(payload.data(), payload.size(), ctx, residuals.data()),
                  kCodecOk);
        const LevelQuantizer quant = codec.quantizer(2);
        for (size_t i = 0; i < base.size(); ++i)
            base[i] = quant.quantize(parent_drawn[i]);
        reconstructChild(residuals.data(), base.data(), 1, n, CodedRegion::whole(n),
                         variant.predictor, q.data());
        for (size_t i = 0; i < q.size(); ++i)
            ASSERT_EQ(quant.reconstruct(q[i]), decoded[i]) << variant.describe() << " sample " << i;

        EXPECT_EQ(codec.decodeResiduals(payload.data(), payload.size(), {n, 0, nullptr, 0},
                                        residuals.data()),
                  kCodecBadHeader)
            << "the root is not split";
        EXPECT_EQ(codec.decodeResiduals(payload.data(), payload.size(), {n, 2, nullptr, 7},
                                        residuals.data()),
                  kCodecBadHeader);
        // v4's contexts read the parent's bins: its CPU half needs the parent, the others not.
        EXPECT_EQ(codec.decodeResiduals(payload.data(), payload.size(), {n, 2, nullptr, 1},
                                        residuals.data()),
                  variant.format == 4 ? kCodecNeedsParent : kCodecOk);
        EXPECT_EQ(codec.capabilities().gpu.cpu_half_reads_parent, variant.format == 4);
        for (size_t size = 0; size < payload.size(); size += 1 + size / 8)
            EXPECT_LT(codec.decodeResiduals(payload.data(), size, ctx, residuals.data()), 0)
                << size;
        std::vector<uint8_t> bad = payload;
        bad[0] ^= 0xff;
        EXPECT_EQ(codec.decodeResiduals(bad.data(), bad.size(), ctx, residuals.data()),
                  kCodecBadHeader);
    }
}

// finishOnCpu(decodeForGpu(payload)) == decode(payload) for every variant and quadrant, with
// the residuals held in 16 bits and in 32 (the escapes): what lets a streamer turn a patch it
// delivered to the GPU into the codes a child's CPU half reads without decoding it again. And
// a payload that is not this patch's is refused, never reconstructed from.
TEST(ProgressiveCodec, FinishOnCpuTurnsTheGpuPayloadIntoDecodesCodes)
{
    struct Unrelated final : GpuPayload {
        size_t bytes() const override { return 0; }
        size_t uploadBytes() const override { return 0; }
    };
    const int n = 33;
    for (const ProgressiveVariant& variant : allVariants()) {
        const ProgressiveCodec codec(0, 3, variant); // step 1: the largest residuals
        ASSERT_TRUE(codec.capabilities().gpu.finishes_on_cpu);
        const std::vector<uint16_t> parent = terrainPatch(n, 5, 30, 1500);
        std::vector<uint16_t> parent_drawn(parent.size());
        codec.reconstruct(parent.data(), {n, 0, nullptr, 0}, parent_drawn.data());
        for (int child = 0; child < 4; ++child) {
            // Child 3 is unrelated to its parent: its residuals need 32 bits.
            const std::vector<uint16_t> codes =
                child == 3 ? terrainPatch(n, 9, 20, 63000) : terrainPatch(n, 6 + child, 20, 1500);
            const PatchContext ctx{n, 2, parent_drawn.data(), child};
            std::vector<uint8_t> payload(codec.encodeBound(ctx));
            payload.resize(codec.encode(payload.data(), payload.size(), codes.data(), ctx));
            std::vector<uint16_t> decoded(codes.size()), finished(codes.size(), 0);
            ASSERT_EQ(codec.decode(decoded.data(), payload.data(), payload.size(), ctx), kCodecOk);
            std::shared_ptr<const GpuPayload> residuals;
            ASSERT_EQ(codec.decodeForGpu(payload.data(), payload.size(), ctx, &residuals),
                      kCodecOk);
            // Other patches coded in between (as on a streamer's worker) leave the codec's
            // per-thread scratch holding another parent in every quadrant.
            for (int other = 0; other < 4; ++other) {
                const PatchContext elsewhere{n, 2, codes.data(), other};
                std::vector<uint8_t> scratch_user(codec.encodeBound(elsewhere));
                codec.encode(scratch_user.data(), scratch_user.size(), parent.data(), elsewhere);
            }
            ASSERT_EQ(codec.finishOnCpu(*residuals, ctx, finished.data()), kCodecOk);
            ASSERT_EQ(finished, decoded) << variant.describe() << " child " << child;
            if (child == 3) {
                EXPECT_FALSE(
                    dynamic_cast<const ProgressiveResiduals&>(*residuals).residuals32.empty())
                    << "the 32-bit storage is exercised";
            }

            EXPECT_EQ(codec.finishOnCpu(*residuals, {n, 2, nullptr, child}, finished.data()),
                      kCodecNeedsParent);
            EXPECT_EQ(codec.finishOnCpu(*residuals, {n, 0, nullptr, 0}, finished.data()),
                      kCodecBadHeader)
                << "the root has no GPU half";
            EXPECT_EQ(codec.finishOnCpu(Unrelated{}, ctx, finished.data()), kCodecBadHeader);
            ProgressiveResiduals other = dynamic_cast<const ProgressiveResiduals&>(*residuals);
            other.region = CodedRegion::covering(n, 17, 0); // another patch's coded region
            EXPECT_EQ(codec.finishOnCpu(other, ctx, finished.data()), kCodecBadHeader);
            other = dynamic_cast<const ProgressiveResiduals&>(*residuals);
            other.assign(std::vector<int32_t>(size_t(n) * n - 1, 0)); // too few residuals
            EXPECT_EQ(codec.finishOnCpu(other, ctx, finished.data()), kCodecBadHeader);
        }
    }
}
