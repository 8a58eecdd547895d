// The fractal codec (the fractal-rings paper's PIFS, with a bound): every sample within E,
// edges that neighbours share decoded identically, the attractor approached by iteration,
// integer decoding that a stored payload pins down, and bad payloads refused.
#include "ridge/codec/fractal_codec.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <vector>

using namespace ridge;

namespace {

constexpr int kN = 65;
// The attractor of AStoredPayloadDecodesToTheSameCodesForever, fixed when it was written.
constexpr uint64_t kAttractorChecksum = 4964452097162249729u;

// Ridges and valleys with noise, on a grid of w × h; patches are cut from it so that
// neighbours share their edge samples exactly as the pyramid's do.
std::vector<uint16_t> terrain(int w, int h, uint32_t seed, int noise)
{
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> jitter(-noise, noise);
    std::vector<uint16_t> v(size_t(w) * h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            v[size_t(y) * w + x] =
                uint16_t(std::clamp(20000 +
                                        int(1800 * std::sin(x * 0.09) * std::cos(y * 0.05) +
                                            700 * std::sin(y * 0.21 + x * 0.03)) +
                                        jitter(rng),
                                    0, 65535));
    return v;
}

std::vector<uint16_t> cut(const std::vector<uint16_t>& grid, int w, int x0, int y0, int n)
{
    std::vector<uint16_t> patch(size_t(n) * n);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
            patch[size_t(y) * n + x] = grid[size_t(y0 + y) * w + x0 + x];
    return patch;
}

std::vector<uint8_t> encode(const FractalCodec& codec, const std::vector<uint16_t>& codes,
                            const PatchContext& ctx)
{
    std::vector<uint8_t> payload(codec.encodeBound(ctx));
    payload.resize(codec.encode(payload.data(), payload.size(), codes.data(), ctx));
    EXPECT_GT(payload.size(), 0u);
    return payload;
}

int maxError(const std::vector<uint16_t>& a, const std::vector<uint16_t>& b)
{
    int worst = 0;
    for (size_t i = 0; i < a.size(); ++i)
        worst = std::max(worst, std::abs(int(a[i]) - int(b[i])));
    return worst;
}

double rmsError(const std::vector<uint16_t>& a, const std::vector<uint16_t>& b)
{
    double sum = 0.0;
    for (size_t i = 0; i < a.size(); ++i)
        sum += double(int(a[i]) - int(b[i])) * (int(a[i]) - int(b[i]));
    return std::sqrt(sum / double(a.size()));
}

} // namespace

TEST(FractalCodec, EverySampleIsWithinTheBoundAtEveryBoundAndPatchSize)
{
    for (const int n : {5, 9, 17, 33, 65, 129})
        for (const int bound : {0, 1, 4, 16, 100}) {
            const std::vector<uint16_t> codes = terrain(n, n, uint32_t(n + bound), 30);
            const FractalCodec codec(bound + 0.7, 4); // ⌊E⌋ is the bound
            const PatchContext ctx{n, 2, nullptr, 0, 0, 0};
            const std::vector<uint8_t> payload = encode(codec, codes, ctx);
            std::vector<uint16_t> out(codes.size());
            ASSERT_EQ(codec.decode(out.data(), payload.data(), payload.size(), ctx), kCodecOk);
            EXPECT_LE(maxError(out, codes), bound) << "n " << n << ", E " << bound;
            std::vector<uint16_t> again(codes.size());
            codec.reconstruct(codes.data(), ctx, again.data());
            EXPECT_EQ(again, out) << "reconstruct is what decode returns";
        }
}

TEST(FractalCodec, NeighboursDecodeTheirSharedEdgeIdentically)
{
    const int w = 2 * kN - 1;
    const std::vector<uint16_t> grid = terrain(w, kN, 3, 60);
    const FractalCodec codec(6.0, 3);
    const PatchContext ctx{kN, 2, nullptr, 0, 0, 0};
    std::vector<uint16_t> left(size_t(kN) * kN), right(left.size());
    const auto l = encode(codec, cut(grid, w, 0, 0, kN), ctx);
    const auto r = encode(codec, cut(grid, w, kN - 1, 0, kN), ctx);
    ASSERT_EQ(codec.decode(left.data(), l.data(), l.size(), ctx), kCodecOk);
    ASSERT_EQ(codec.decode(right.data(), r.data(), r.size(), ctx), kCodecOk);
    for (int y = 0; y < kN; ++y)
        ASSERT_EQ(left[size_t(y) * kN + kN - 1], right[size_t(y) * kN]) << "row " << y;
}

TEST(FractalCodec, IterationsApproachTheAttractor)
{
    // The paper's observation: the iterates converge after about 8 applications of T. Without
    // corrections, the error against the patch falls from the start image's to the
    // attractor's collage error.
    const std::vector<uint16_t> codes = terrain(kN, kN, 5, 4);
    const FractalCodec codec(0.0, 1, FractalVariant{10, 0});
    const PatchContext ctx{kN, 0, nullptr, 0, 0, 0};
    const std::vector<uint8_t> payload = encode(codec, codes, ctx);
    std::vector<double> rms;
    std::vector<uint16_t> a(codes.size()), previous(codes.size());
    for (int i = 0; i <= 10; ++i) {
        ASSERT_EQ(codec.decodeAttractor(a.data(), payload.data(), payload.size(), ctx, i),
                  kCodecOk);
        rms.push_back(rmsError(a, codes));
        if (i == 10) { // converged: one more application changes almost nothing
            EXPECT_LE(maxError(a, previous), 2);
        }
        previous = a;
    }
    EXPECT_LT(rms[8], 0.5 * rms[0]) << "start " << rms[0] << ", 8 iterations " << rms[8];
    EXPECT_LT(rms[8], 40.0);
}

TEST(FractalCodec, AStoredPayloadDecodesToTheSameCodesForever)
{
    // Integer decoding: a payload written once (below, by this codec at E = 2, 8 iterations,
    // full search, from the 9 × 9 patch `codes`) decodes to the same codes on every machine and
    // in every later version — a GPU decoder must match them too. The attractor is pinned by
    // a checksum fixed at the time of writing, the full decode by the bound.
    const int n = 9;
    std::vector<uint16_t> codes(size_t(n) * n);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
            codes[size_t(y) * n + x] = uint16_t(1000 + 13 * x * x - 7 * y * x + 29 * y);
    static const std::vector<uint8_t> kPayload = {
        70,  1,   8,   0,   2,  0,   54, 0,   0,  0,   45,  0,   0,   0,  40,  181, 47,  253, 32,
        45,  105, 1,   0,   0,  0,   1,  0,   0,  0,   0,   0,   1,   1,  0,   1,   2,   0,   1,
        1,   1,   1,   7,   24, 1,   3,  22,  1,  252, 19,  0,   194, 12, 163, 5,   128, 20,  147,
        11,  155, 8,   216, 17, 251, 3,  163, 12, 250, 15,  40,  181, 47, 253, 32,  36,  33,  1,
        0,   144, 3,   6,   14, 26,  38, 46,  58, 66,  78,  239, 1,   15, 7,   4,   14,  24,  36,
        44,  56,  233, 1,   12, 10,  12, 12,  12, 12,  240, 1,   9,   11, 9,   11,  9,   9,   40,
        181, 47,  253, 32,  49, 137, 1,  0,   1,  9,   0,   19,  12,  1,  16,  2,   4,   4,   41,
        5,   20,  14,  10,  6,  10,  49, 7,   1,  14,  13,  13,  7,   2,  18,  16,  0,   5,   9,
        1,   7,   14,  3,   6,  2,   1,  0,   27, 3,   14,  2,   10,  4,  4,   35,  5,   5,   2};
    const FractalCodec codec(2.0, 1, FractalVariant{8, 0});
    const PatchContext ctx{n, 0, nullptr, 0, 0, 0};
    std::vector<uint16_t> attractor(codes.size()), decoded(codes.size());
    ASSERT_EQ(codec.decodeAttractor(attractor.data(), kPayload.data(), kPayload.size(), ctx, 8),
              kCodecOk);
    uint64_t checksum = 0;
    for (const uint16_t v : attractor)
        checksum = checksum * 1000003u + v;
    EXPECT_EQ(checksum, kAttractorChecksum) << "the integer decoder changed";
    ASSERT_EQ(codec.decode(decoded.data(), kPayload.data(), kPayload.size(), ctx), kCodecOk);
    EXPECT_LE(maxError(decoded, codes), 2);
    // The encoder writes version 2: the same header and sections (zstd's output is Debian
    // 12's libzstd's) with the bound of each partial decode between them, and it decodes the
    // same.
    const std::vector<uint8_t> v2 = encode(codec, codes, ctx);
    ASSERT_EQ(v2.size(), kPayload.size() + 16);
    EXPECT_EQ(v2[1], 2);
    EXPECT_TRUE(std::equal(kPayload.begin() + 2, kPayload.begin() + 14, v2.begin() + 2));
    EXPECT_TRUE(std::equal(kPayload.begin() + 14, kPayload.end(), v2.begin() + 30));
    const std::vector<uint8_t> table(v2.begin() + 14, v2.begin() + 30);
    EXPECT_EQ(table, (std::vector<uint8_t>{80, 2, 138, 1, 174, 0, 52, 0, 19, 0, 7, 0, 2, 0, 1, 0}))
        << "max |partial_k − full| for k = 0..7: 592, 394, 174, 52, 19, 7, 2, 1 codes";
    std::vector<uint16_t> again(codes.size());
    ASSERT_EQ(codec.decode(again.data(), v2.data(), v2.size(), ctx), kCodecOk);
    EXPECT_EQ(again, decoded);
    // Every partial decode is within its stored bound of the full one.
    for (int k = 0; k <= 8; ++k) {
        ASSERT_EQ(codec.decodePartial(again.data(), v2.data(), v2.size(), ctx, k), kCodecOk);
        const int bound = k == 8 ? 0 : table[size_t(2 * k)] | table[size_t(2 * k + 1)] << 8;
        EXPECT_LE(maxError(again, decoded), bound) << k << " iterations";
        if (k == 7) {
            EXPECT_EQ(maxError(again, decoded), bound) << "the bound is the measured maximum";
        }
    }
}

TEST(FractalCodec, BadPayloadsAreRefusedAndNeverReadOutside)
{
    const std::vector<uint16_t> codes = terrain(33, 33, 9, 40);
    const FractalCodec codec(3.0, 2);
    const PatchContext ctx{33, 1, nullptr, 0, 0, 0};
    const std::vector<uint8_t> good = encode(codec, codes, ctx);
    std::vector<uint16_t> out(codes.size());
    for (size_t keep = 0; keep < good.size(); ++keep)
        EXPECT_LT(codec.decode(out.data(), good.data(), keep, ctx), 0) << "truncated to " << keep;
    std::vector<uint8_t> longer = good;
    longer.push_back(0);
    EXPECT_EQ(codec.decode(out.data(), longer.data(), longer.size(), ctx), kCodecTrailingBytes);
    // Header fields: magic, version, iterations 0 and 33, flags, a bound other than the codec's.
    for (const auto& [at, value] : std::vector<std::pair<size_t, uint8_t>>{
             {0, 'G'}, {1, 3}, {1, 0}, {2, 0}, {2, 33}, {3, 1}, {4, 4}}) {
        std::vector<uint8_t> bad = good;
        bad[at] = value;
        EXPECT_EQ(codec.decode(out.data(), bad.data(), bad.size(), ctx), kCodecBadHeader)
            << "byte " << at;
    }
    // Any single flipped byte: refused, or a patch (every sample still a code).
    std::mt19937 rng(1);
    for (int trial = 0; trial < 2000; ++trial) {
        std::vector<uint8_t> bad = good;
        bad[rng() % bad.size()] ^= uint8_t(1 + rng() % 255);
        const int status = codec.decode(out.data(), bad.data(), bad.size(), ctx);
        EXPECT_LE(status, 0);
    }
}

TEST(FractalCodec, ThePapersModeSendsTheTransformsAloneAndPromisesNoBound)
{
    const std::vector<uint16_t> codes = terrain(33, 33, 11, 30);
    const PatchContext ctx{33, 1, nullptr, 0, 0, 0};
    FractalVariant paper_variant;
    paper_variant.paper = true;
    const FractalCodec paper(0.0, 2, paper_variant), bounded(3.0, 2);
    EXPECT_FALSE(std::isfinite(paper.levelErrorBound(1)));
    const std::vector<uint8_t> p = encode(paper, codes, ctx), b = encode(bounded, codes, ctx);
    EXPECT_EQ(p[3], 1) << "the paper's flag";
    EXPECT_LT(p.size(), b.size()) << "no edges, no corrections";
    // Decodes to the attractor itself, iterated without pinning.
    std::vector<uint16_t> out(codes.size()), attractor(codes.size());
    ASSERT_EQ(paper.decode(out.data(), p.data(), p.size(), ctx), kCodecOk);
    ASSERT_EQ(paper.decodeAttractor(attractor.data(), p.data(), p.size(), ctx, 8), kCodecOk);
    EXPECT_EQ(out, attractor);
    EXPECT_GT(maxError(out, codes), 3) << "nothing holds it within a bound";
    // Neither mode decodes the other's payloads.
    EXPECT_EQ(bounded.decode(out.data(), p.data(), p.size(), ctx), kCodecBadHeader);
    EXPECT_EQ(paper.decode(out.data(), b.data(), b.size(), ctx), kCodecBadHeader);
    // The GPU's payload: nothing pinned, no corrections.
    std::shared_ptr<const GpuPayload> gpu;
    ASSERT_EQ(paper.decodeForGpu(p.data(), p.size(), ctx, &gpu), kCodecOk);
    const auto& f = static_cast<const FractalPayload&>(*gpu);
    EXPECT_FALSE(f.pinned);
    EXPECT_TRUE(std::all_of(f.samples.begin(), f.samples.end(), [](int32_t v) { return v == 0; }));
    // Bytes after the transforms are refused.
    std::vector<uint8_t> longer = p;
    longer.push_back(0);
    EXPECT_LT(paper.decode(out.data(), longer.data(), longer.size(), ctx), 0);
}
