// The per-patch sample flags of format versions 4 and 5 (archive/sample_flags_storage.h,
// docs/FORMAT.md "Sample flags"): golden bytes of the one-byte kinds and of a context-coded
// bitmap, both bitmap kinds' round trips, and every malformed encoding refused with the field
// named.
#include "context_bitmap.h" // src/archive: crafted kind-3 streams
#include "ridge/archive/sample_flags_storage.h"

#include <gtest/gtest.h>

#include <zstd.h>

using namespace ridge;
using namespace ridge::archive;

namespace {

constexpr int kN = 5;       // a patch of 5 x 5 samples: the smallest the format allows
constexpr uint32_t kV4 = 4; // zstd bitmaps (kind 2)

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

std::string unpack(const std::vector<uint8_t>& bytes, const PatchValidity* validity = nullptr,
                   uint32_t version = kV4)
{
    PatchSampleFlags out;
    size_t consumed = 0;
    return unpackSampleFlags(bytes.data(), bytes.size(), kN, validity, out, consumed, version);
}

std::string hex(const std::vector<uint8_t>& b)
{
    std::string s;
    for (const uint8_t v : b)
        s += "0123456789abcdef"[v >> 4], s += "0123456789abcdef"[v & 15];
    return s;
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
    for (const uint32_t version : {kV4, kFormatVersion}) {
        SCOPED_TRACE(version);
        std::vector<uint8_t> bytes = packSampleFlags(f, kN, version);
        ASSERT_GT(bytes.size(), 5u);
        EXPECT_EQ(bytes[0], version == kV4 ? 2 : 3);
        const size_t encoded = bytes.size();
        bytes.push_back(0x50); // the payload that follows in a blob
        PatchSampleFlags out;
        size_t consumed = 0;
        EXPECT_EQ(
            unpackSampleFlags(bytes.data(), bytes.size(), kN, nullptr, out, consumed, version), "");
        EXPECT_EQ(consumed, encoded);
        EXPECT_EQ(out.kind, PatchSampleFlags::Kind::Mixed);
        EXPECT_EQ(out.flags, f.flags);
        EXPECT_TRUE(out.water(0, 0));
        EXPECT_TRUE(out.filled(4, 4));
        // Each version has one bitmap kind: the other's bytes are refused, naming it.
        EXPECT_NE(unpack(bytes, nullptr, version == kV4 ? kFormatVersion : kV4)
                      .find(version == kV4 ? "codes bitmaps as kind 3" : "codes bitmaps as kind 2"),
                  std::string::npos);
    }
}

TEST(SampleFlagsStorage, ContextCodedBitmapBytesArePinned)
{
    // Kind 3, planes 3 (water and filled), u32 stream size, the range-coded planes: a change
    // of these bytes is a format change.
    EXPECT_EQ(hex(packSampleFlags(mixed(), kN)), "03030a000000009193b457fd4957c000");
    // Water alone: the filled plane is left out (plane byte 1).
    PatchSampleFlags coast{PatchSampleFlags::Kind::Mixed, kN, std::vector<uint8_t>(kN * kN, 0)};
    for (int k = 0; k < kN * kN; ++k)
        coast.flags[k] = k % kN + k / kN < 4 ? kSampleWater : 0;
    const std::vector<uint8_t> bytes = packSampleFlags(coast, kN);
    ASSERT_GT(bytes.size(), 6u);
    EXPECT_EQ(bytes[1], 1);
    PatchSampleFlags out;
    size_t consumed = 0;
    ASSERT_EQ(unpackSampleFlags(bytes.data(), bytes.size(), kN, nullptr, out, consumed), "");
    EXPECT_EQ(out.flags, coast.flags);
}

// A real coastline (a quarter disc of water) costs well under the zstd bitmap's bytes.
TEST(SampleFlagsStorage, ContextCodingBeatsTheZstdBitmapOnACoast)
{
    const int n = 129;
    PatchSampleFlags coast{PatchSampleFlags::Kind::Mixed, n, std::vector<uint8_t>(n * n, 0)};
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
            if (x * x + y * y + 40 * ((x * 7 + y * 13) % 5) < 90 * 90)
                coast.flags[size_t(y) * n + x] = kSampleWater;
    const std::vector<uint8_t> v5 = packSampleFlags(coast, n), v4 = packSampleFlags(coast, n, kV4);
    EXPECT_LT(double(v5.size()), 0.8 * double(v4.size())) << v5.size() << " vs " << v4.size();
    PatchSampleFlags out;
    size_t consumed = 0;
    ASSERT_EQ(unpackSampleFlags(v5.data(), v5.size(), n, nullptr, out, consumed), "");
    EXPECT_EQ(out.flags, coast.flags);
}

TEST(SampleFlagsStorage, RefusesAnUnknownKind)
{
    EXPECT_NE(unpack({4}).find("sample flags kind is 4"), std::string::npos);
    EXPECT_NE(unpack({4}, nullptr, kFormatVersion).find("or 3 (context-coded bitmaps)"),
              std::string::npos);
    EXPECT_NE(unpack({}).find("sample flags missing"), std::string::npos);
}

TEST(SampleFlagsStorage, RefusesAMalformedContextCodedBitmap)
{
    const std::vector<uint8_t> good = packSampleFlags(mixed(), kN);
    ASSERT_EQ(good[0], 3);
    auto refused = [&](std::vector<uint8_t> b, const std::string& phrase) {
        const std::string why = unpack(b, nullptr, kFormatVersion);
        EXPECT_NE(why.find(phrase), std::string::npos) << phrase << ": " << why;
    };
    refused({3, 3, 0, 0}, "truncated before its stream size");
    std::vector<uint8_t> b = good;
    b[1] = 0;
    refused(b, "plane byte is 0");
    b[1] = 4;
    refused(b, "plane byte is 4");
    b = good;
    b[2] = uint8_t(b[2] + 1); // one byte more than there is
    refused(b, "runs past the blob");
    // The stream cut short, with its size adjusted, and a byte too many inside the stream.
    b = good;
    b.pop_back();
    b[2] = uint8_t(b[2] - 1);
    refused(b, "stream is corrupt");
    b = good;
    b.push_back(0);
    b[2] = uint8_t(b[2] + 1);
    refused(b, "stream is corrupt");
    // A plane that is coded must have a set bit; a uniform patch is kind 0 or 1.
    PatchSampleFlags water_only = mixed();
    for (uint8_t& v : water_only.flags)
        v &= kSampleWater;
    std::vector<uint8_t> w = packSampleFlags(water_only, kN);
    ASSERT_EQ(w[1], 1);
    std::vector<uint8_t> claims_filled = w;
    claims_filled[1] = 3; // claims a filled plane the stream does not hold: decoding fails
    refused(claims_filled, "stream is corrupt");
    // A stream that does code an all-zero filled plane.
    std::vector<uint8_t> water(kN * kN), none(kN * kN, 0);
    for (int k = 0; k < kN * kN; ++k)
        water[k] = water_only.flags[k] != 0;
    const std::vector<uint8_t> stream = detail::encodeContextBitmap({&water, &none}, kN);
    std::vector<uint8_t> crafted{3, 3, uint8_t(stream.size()), 0, 0, 0};
    crafted.insert(crafted.end(), stream.begin(), stream.end());
    refused(crafted, "codes an empty filled plane");
    // Water everywhere and no filled sample is kind 1, however it is coded.
    std::vector<uint8_t> all(kN * kN, 1);
    const std::vector<uint8_t> all_stream = detail::encodeContextBitmap({&all}, kN);
    std::vector<uint8_t> uniform{3, 1, uint8_t(all_stream.size()), 0, 0, 0};
    uniform.insert(uniform.end(), all_stream.begin(), all_stream.end());
    refused(uniform, "must be stored as kind 1");
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
    EXPECT_EQ(unpack(bytes, &validity, kFormatVersion), "");
    validity.samples[3] = 0; // sample (3, 0) is water in mixed()
    EXPECT_NE(unpack(bytes, &validity, kFormatVersion)
                  .find("sample (3, 0) is flagged water but is not valid"),
              std::string::npos);
    const PatchValidity none{PatchValidity::Kind::NoneValid, kN, {}, {}};
    EXPECT_NE(unpack({1}, &none).find("not valid"), std::string::npos);
    EXPECT_EQ(unpack({0}, &none), "");
}
