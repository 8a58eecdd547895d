#include "ridge/codec/lossless_codec.h"
#include "ridge/core/error.h"

#include <gtest/gtest.h>

#include <random>
#include <vector>

using namespace ridge;

namespace {

// A rough but deterministic terrain-like patch: smooth ramps plus noise.
std::vector<uint16_t> terrainPatch(int n, uint32_t seed, int noise)
{
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> jitter(-noise, noise);
    std::vector<uint16_t> v(n * n);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
            v[y * n + x] =
                static_cast<uint16_t>(std::clamp(30000 + 40 * x - 25 * y + jitter(rng), 0, 65535));
    return v;
}

std::vector<uint8_t> encode(const HeightCodec& codec, const std::vector<uint16_t>& codes, int n)
{
    const PatchContext ctx{n, 0, nullptr, 0};
    std::vector<uint8_t> out(codec.encodeBound(ctx));
    out.resize(codec.encode(out.data(), out.size(), codes.data(), ctx));
    return out;
}

} // namespace

TEST(LosslessCodec, RoundTripsTerrainExactly)
{
    for (int n : {5, 65, 129}) {
        for (const char* name : {"lossless", "raw"}) {
            const std::unique_ptr<HeightCodec> codec = makeCodec(name);
            const std::vector<uint16_t> codes = terrainPatch(n, 42 + n, 30);
            const std::vector<uint8_t> payload = encode(*codec, codes, n);
            ASSERT_FALSE(payload.empty());
            std::vector<uint16_t> back(n * n);
            ASSERT_EQ(
                codec->decode(back.data(), payload.data(), payload.size(), {n, 0, nullptr, 0}),
                kCodecOk);
            EXPECT_EQ(back, codes) << name << " n=" << n;
        }
    }
}

TEST(LosslessCodec, RoundTripsExtremeAndRandomCodes)
{
    std::mt19937 rng(7);
    std::uniform_int_distribution<int> any(0, 65535);
    const LosslessCodec codec;
    std::vector<uint16_t> codes(129 * 129);
    for (auto& c : codes)
        c = static_cast<uint16_t>(any(rng)); // residuals wrap around mod 2^16
    codes[0] = 0;
    codes[1] = 65535;
    const std::vector<uint8_t> payload = encode(codec, codes, 129);
    std::vector<uint16_t> back(codes.size());
    ASSERT_EQ(codec.decode(back.data(), payload.data(), payload.size(), {129, 0, nullptr, 0}),
              kCodecOk);
    EXPECT_EQ(back, codes);
}

TEST(LosslessCodec, CompressesSmoothTerrain)
{
    const LosslessCodec codec;
    const std::vector<uint16_t> codes = terrainPatch(129, 1, 2);
    EXPECT_LT(encode(codec, codes, 129).size(), codes.size() * 2 / 3);
}

TEST(LosslessCodec, RejectsTruncatedPayloadsAtEveryLength)
{
    const LosslessCodec codec;
    const std::vector<uint16_t> codes = terrainPatch(33, 3, 50);
    const std::vector<uint8_t> payload = encode(codec, codes, 33);
    std::vector<uint16_t> back(codes.size());
    for (size_t len = 0; len < payload.size(); ++len)
        EXPECT_LT(codec.decode(back.data(), payload.data(), len, {33, 0, nullptr, 0}), 0) << len;
}

TEST(LosslessCodec, RejectsTrailingBytesAndBadHeaders)
{
    const LosslessCodec codec;
    const std::vector<uint16_t> codes = terrainPatch(33, 4, 50);
    std::vector<uint8_t> payload = encode(codec, codes, 33);
    std::vector<uint16_t> back(codes.size());
    std::vector<uint8_t> longer = payload;
    longer.push_back(0);
    EXPECT_EQ(codec.decode(back.data(), longer.data(), longer.size(), {33, 0, nullptr, 0}),
              kCodecTrailingBytes);
    payload[1] = 99; // version from the future
    EXPECT_EQ(codec.decode(back.data(), payload.data(), payload.size(), {33, 0, nullptr, 0}),
              kCodecBadHeader);
}

TEST(LosslessCodec, RejectsAPayloadOfTheWrongPatchSize)
{
    const LosslessCodec codec;
    const std::vector<uint16_t> codes = terrainPatch(33, 5, 50);
    const std::vector<uint8_t> payload = encode(codec, codes, 33);
    std::vector<uint16_t> back(65 * 65);
    EXPECT_EQ(codec.decode(back.data(), payload.data(), payload.size(), {65, 0, nullptr, 0}),
              kCodecCorrupt);
}

TEST(LosslessCodec, SurvivesEveryFlippedByteWithoutCrashing)
{
    // The archive's CRC catches corruption first; the decoder must still never misbehave.
    const LosslessCodec codec;
    const std::vector<uint16_t> codes = terrainPatch(33, 6, 50);
    const std::vector<uint8_t> payload = encode(codec, codes, 33);
    std::vector<uint16_t> back(codes.size());
    for (size_t i = 0; i < payload.size(); ++i) {
        std::vector<uint8_t> bad = payload;
        bad[i] ^= 0x5a;
        const int status = codec.decode(back.data(), bad.data(), bad.size(), {33, 0, nullptr, 0});
        EXPECT_TRUE(status == kCodecOk || status < 0);
    }
}

TEST(CodecRegistry, KnowsItsCodecsByNameAndId)
{
    EXPECT_EQ(makeCodec("lossless")->id(), kLosslessCodecId);
    EXPECT_EQ(makeCodec(kRaw16CodecId)->name(), std::string("raw"));
    EXPECT_THROW(makeCodec("jpeg9000"), Error);
    EXPECT_EQ(makeCodec(static_cast<CodecId>(77)), nullptr);
}
