// The per-patch sample flags of format version 4 (archive/sample_flags_storage.h,
// docs/FORMAT.md "Sample flags"): golden bytes of the one-byte kinds, a bitmap's round trip,
// and every malformed encoding refused with the field named.
#include "ridge/archive/sample_flags_storage.h"

#include <gtest/gtest.h>

#include <zstd.h>

using namespace ridge;
using namespace ridge::archive;

namespace {

constexpr int kN = 5; // a patch of 5 x 5 samples: the smallest the format allows

PatchSampleFlags mixed()
{
    PatchSampleFlags f{PatchSampleFlags::Kind::Mixed, kN, std::vector<uint8_t>(kN * kN, 0)};
    for (int k = 0; k < kN * kN; ++k)
        f.flags[k] = k % 3 == 0 ? kSampleWater : k % 7 == 0 ? kSampleFilled : 0;
    f.flags[24] = kSampleWater | kSampleFilled; // a filled void judged water
    return f;
}

// A kind-2 encoding of raw bitmap bytes, for malformed contents.
std::vector<uint8_t> frameOf(const std::vector<uint8_t>& raw)
{
    std::vector<uint8_t> out(5 + ZSTD_compressBound(raw.size()));
    const size_t z = ZSTD_compress(out.data() + 5, out.size() - 5, raw.data(), raw.size(), 3);
    out[0] = 2;
    for (int k = 0; k < 4; ++k)
        out[1 + k] = uint8_t(z >> (8 * k));
    out.resize(5 + z);
    return out;
}

std::string unpack(const std::vector<uint8_t>& bytes, const PatchValidity* validity = nullptr)
{
    PatchSampleFlags out;
    size_t consumed = 0;
    return unpackSampleFlags(bytes.data(), bytes.size(), kN, validity, out, consumed);
}

} // namespace

TEST(SampleFlagsStorage, OneByteKindsArePinned)
{
    EXPECT_EQ(packSampleFlags({PatchSampleFlags::Kind::None, kN, {}}, kN), std::vector<uint8_t>{0});
    EXPECT_EQ(packSampleFlags({PatchSampleFlags::Kind::AllWater, kN, {}}, kN),
              std::vector<uint8_t>{1});
    // Uniform bitmaps are written as their one-byte kinds.
    EXPECT_EQ(
        packSampleFlags({PatchSampleFlags::Kind::Mixed, kN, std::vector<uint8_t>(kN * kN, 0)}, kN),
        std::vector<uint8_t>{0});
    EXPECT_EQ(
        packSampleFlags(
            {PatchSampleFlags::Kind::Mixed, kN, std::vector<uint8_t>(kN * kN, kSampleWater)}, kN),
        std::vector<uint8_t>{1});
}

TEST(SampleFlagsStorage, BitmapsRoundTripAndStopAtTheirEnd)
{
    const PatchSampleFlags f = mixed();
    std::vector<uint8_t> bytes = packSampleFlags(f, kN);
    ASSERT_GT(bytes.size(), 5u);
    EXPECT_EQ(bytes[0], 2);
    const size_t encoded = bytes.size();
    bytes.push_back(0x50); // the payload that follows in a blob
    PatchSampleFlags out;
    size_t consumed = 0;
    EXPECT_EQ(unpackSampleFlags(bytes.data(), bytes.size(), kN, nullptr, out, consumed), "");
    EXPECT_EQ(consumed, encoded);
    EXPECT_EQ(out.kind, PatchSampleFlags::Kind::Mixed);
    EXPECT_EQ(out.flags, f.flags);
    EXPECT_TRUE(out.water(0, 0));
    EXPECT_TRUE(out.filled(4, 4));
}

TEST(SampleFlagsStorage, RefusesAnUnknownKind)
{
    EXPECT_NE(unpack({3}).find("sample flags kind is 3"), std::string::npos);
    EXPECT_NE(unpack({}).find("sample flags missing"), std::string::npos);
}

TEST(SampleFlagsStorage, RefusesAUniformBitmap)
{
    std::vector<uint8_t> raw((2 * kN * kN + 7) / 8, 0);
    EXPECT_NE(unpack(frameOf(raw)).find("must be stored as kind 0"), std::string::npos);
    for (int b = 0; b < kN * kN; ++b)
        raw[b / 8] |= uint8_t(1u << (b % 8)); // every water bit, no filled bit
    EXPECT_NE(unpack(frameOf(raw)).find("must be stored as kind 1"), std::string::npos);
}

TEST(SampleFlagsStorage, RefusesBitsPastTheLastAndContentOfAnotherSize)
{
    std::vector<uint8_t> raw((2 * kN * kN + 7) / 8, 0);
    raw[0] = 1;
    raw.back() |= 0x80; // bit 55 of 50
    EXPECT_NE(unpack(frameOf(raw)).find("non-zero bit past its last"), std::string::npos);
    raw.back() = 0;
    raw.push_back(0);
    EXPECT_NE(unpack(frameOf(raw)).find("content size"), std::string::npos);
}

TEST(SampleFlagsStorage, RefusesAFlagOnASampleThatIsNotValid)
{
    PatchValidity validity{PatchValidity::Kind::Mixed, kN, std::vector<uint8_t>(kN * kN, 1),
                           std::vector<uint8_t>((kN - 1) * (kN - 1), 1)};
    const std::vector<uint8_t> bytes = packSampleFlags(mixed(), kN);
    EXPECT_EQ(unpack(bytes, &validity), "");
    validity.samples[3] = 0; // sample (3, 0) is water in mixed()
    EXPECT_NE(unpack(bytes, &validity).find("sample (3, 0) is flagged water but is not valid"),
              std::string::npos);
    const PatchValidity none{PatchValidity::Kind::NoneValid, kN, {}, {}};
    EXPECT_NE(unpack({1}, &none).find("not valid"), std::string::npos);
    EXPECT_EQ(unpack({0}, &none), "");
}
