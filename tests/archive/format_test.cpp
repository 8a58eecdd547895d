#include "ridge/archive/archive_reader.h"
#include "ridge/archive/block_error_storage.h"
#include "ridge/archive/format.h"
#include "ridge/core/crc32.h"
#include "ridge/core/error.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "test_support.h"

using namespace ridge;
using namespace ridge::archive;

namespace {

Header sampleHeader()
{
    Header h;
    h.width = 301;
    h.height = 203;
    h.patch_size = 129;
    h.level_count = 3;
    h.block_cells = 8;
    h.block_levels = 3;
    h.codec_id = 1;
    h.filter_id = 0;
    h.height_scale = 1.0;
    h.height_offset = -32768.0;
    h.spacing_x = 82.25;
    h.spacing_y = 92.5;
    h.metadata_offset = 160;
    h.metadata_size = 2;
    h.metadata_crc32 = 0x12345678;
    h.index_offset = 1000;
    h.index_crc32 = 0x9abcdef0;
    h.codec_tables_offset = 900;
    h.codec_tables_size = 64;
    h.codec_tables_crc32 = 0xcafef00d;
    return h;
}

} // namespace

TEST(Crc32, MatchesTheStandardCheckValue)
{
    EXPECT_EQ(crc32("123456789", 9), 0xCBF43926u); // CRC-32/ISO-HDLC check value
    EXPECT_EQ(crc32("", 0), 0u);
}

// Pins the header layout: a change here is a format change and needs a version bump. (Version
// 2 added the blobs' validity masks; version 3 the codec tables fields at 140..155, reserved
// zero before; version 4 the blobs' sample flags, the header unchanged.)
TEST(ArchiveFormat, HeaderBytesArePinned)
{
    uint8_t bytes[kHeaderSize];
    serializeHeader(sampleHeader(), bytes);
    EXPECT_EQ(std::memcmp(bytes, "RIDGEARC", 8), 0);
    auto u32 = [&](size_t o) {
        uint32_t v;
        std::memcpy(&v, bytes + o, 4);
        return v;
    };
    auto f64 = [&](size_t o) {
        double v;
        std::memcpy(&v, bytes + o, 8);
        return v;
    };
    EXPECT_EQ(u32(8), 6u);    // version
    EXPECT_EQ(u32(12), 160u); // header size
    EXPECT_EQ(u32(16), 301u); // width
    EXPECT_EQ(u32(20), 203u); // height
    EXPECT_EQ(u32(24), 129u); // patch size
    EXPECT_EQ(u32(28), 3u);   // levels
    EXPECT_EQ(u32(32), 8u);   // block cells
    EXPECT_EQ(u32(36), 3u);   // block levels
    EXPECT_EQ(u32(40), 1u);   // codec
    EXPECT_EQ(f64(56), -32768.0);
    EXPECT_EQ(f64(64), 82.25);
    EXPECT_EQ(f64(80), 0.0); // quantization error
    EXPECT_EQ(f64(88), 0.0); // reserved
    EXPECT_EQ(u32(120), 2u); // metadata size
    EXPECT_EQ(u32(124), 0x12345678u);
    EXPECT_EQ(u32(136), 0x9abcdef0u);
    uint64_t tables_offset;
    std::memcpy(&tables_offset, bytes + 140, 8);
    EXPECT_EQ(tables_offset, 900u); // codec tables offset
    EXPECT_EQ(u32(148), 64u);       // codec tables size
    EXPECT_EQ(u32(152), 0xcafef00du);
    EXPECT_EQ(u32(156), crc32(bytes, 156));
}

TEST(ArchiveFormat, HeaderRoundTrips)
{
    uint8_t bytes[kHeaderSize];
    serializeHeader(sampleHeader(), bytes);
    Header back;
    ASSERT_EQ(parseHeader(bytes, back), "");
    EXPECT_EQ(back.width, 301u);
    EXPECT_EQ(back.spacing_y, 92.5);
    EXPECT_EQ(back.index_offset, 1000u);
}

TEST(ArchiveFormat, ParseRejectsBadMagicNewerVersionsAndCorruptHeaders)
{
    uint8_t bytes[kHeaderSize];
    serializeHeader(sampleHeader(), bytes);
    Header h;
    uint8_t bad[kHeaderSize];
    std::memcpy(bad, bytes, kHeaderSize);
    bad[0] = 'X';
    EXPECT_NE(parseHeader(bad, h).find("magic"), std::string::npos);
    std::memcpy(bad, bytes, kHeaderSize);
    bad[8] = 7;
    EXPECT_NE(parseHeader(bad, h).find("not supported"), std::string::npos);
    for (const uint8_t known : {1, 2, 3, 4, 5, 6}) { // every version this reader knows
        if (known < 3)                               // their bytes 140..155 are reserved: zero
            serializeHeader(
                [] {
                    Header z = sampleHeader();
                    z.codec_tables_offset = 0;
                    z.codec_tables_size = 0;
                    z.codec_tables_crc32 = 0;
                    return z;
                }(),
                bytes);
        else
            serializeHeader(sampleHeader(), bytes);
        std::memcpy(bad, bytes, kHeaderSize);
        bad[8] = known;
        const uint32_t crc = crc32(bad, 156);
        std::memcpy(bad + 156, &crc, 4);
        EXPECT_EQ(parseHeader(bad, h), "") << "version " << int(known);
        EXPECT_EQ(h.version, known);
    }
    for (size_t i = 12; i < kHeaderSize; ++i) {
        std::memcpy(bad, bytes, kHeaderSize);
        bad[i] ^= 0x10;
        EXPECT_NE(parseHeader(bad, h), "") << "flipped header byte " << i;
    }
}

TEST(ArchiveFormat, IndexRecordRoundTrips)
{
    PatchRecord r;
    r.level = 4;
    r.x = 7;
    r.y = 9;
    r.block_errors_size = 77;
    r.offset = 1ull << 40;
    r.size = 12345;
    r.crc32 = 0xdeadbeef;
    r.min_height = -85.f;
    r.max_height = 4404.f;
    r.err_appr = 3.5f;
    r.err = 4.f;
    uint8_t bytes[kIndexEntrySize];
    serializeRecord(r, bytes);
    const PatchRecord back = parseRecord(bytes);
    EXPECT_EQ(back.offset, r.offset);
    EXPECT_EQ(back.crc32, r.crc32);
    EXPECT_EQ(back.max_height, r.max_height);
    EXPECT_EQ(back.err, r.err);
}

TEST(ArchiveFormat, FloatRoundingNeverMovesABoundInwards)
{
    for (double v : {0.1, 1234.567891, -85.3333333, 8848.000001, 1e-9}) {
        EXPECT_LE(double(floatDown(v)), v);
        EXPECT_GE(double(floatUp(v)), v);
        EXPECT_LT(double(floatUp(v)) - double(floatDown(v)), std::fabs(v) * 1e-6 + 1e-30);
    }
}

TEST(BlockErrorStorage, RoundsUpWithAFineQuantumForSmallErrors)
{
    const float lambda_codes[4] = {0.f, 0.25f, 10.f, 100.f};
    const std::vector<uint8_t> packed = packBlockErrors(lambda_codes, 4, 0.5);
    float back[4];
    ASSERT_TRUE(unpackBlockErrors(packed.data(), packed.size(), 4, back));
    EXPECT_EQ(back[0], 0.f);
    EXPECT_GE(back[1], 0.125f);
    EXPECT_GE(back[2], 5.f);
    EXPECT_LE(back[2], 5.f + 0.5f / 16 + 1e-6f); // quantum = scale / 16 here
    EXPECT_GE(back[3], 50.f);
}

TEST(BlockErrorStorage, HugeErrorsGetACoarserQuantumInsteadOfSaturating)
{
    const float lambda_codes[2] = {1.f, 60000.f};
    const std::vector<uint8_t> packed = packBlockErrors(lambda_codes, 2, 1.0);
    float back[2];
    ASSERT_TRUE(unpackBlockErrors(packed.data(), packed.size(), 2, back));
    EXPECT_FALSE(std::isinf(back[1]));
    EXPECT_GE(back[1], 60000.f);
    EXPECT_LT(back[1], 60002.f);
    EXPECT_GE(back[0], 1.f);
}

TEST(BlockErrorStorage, RejectsTruncatedOrMismatchedFrames)
{
    const float lambda_codes[4] = {1.f, 2.f, 3.f, 4.f};
    const std::vector<uint8_t> packed = packBlockErrors(lambda_codes, 4, 1.0);
    float back[5];
    EXPECT_FALSE(unpackBlockErrors(packed.data(), packed.size() - 1, 4, back));
    EXPECT_FALSE(unpackBlockErrors(packed.data(), packed.size(), 5, back));
    EXPECT_FALSE(unpackBlockErrors(packed.data(), 3, 4, back));
    std::vector<uint8_t> bad = packed;
    bad[3] = 0xff; // quantum becomes NaN
    EXPECT_FALSE(unpackBlockErrors(bad.data(), bad.size(), 4, back));
}

TEST(ArchiveReader, RejectsFilesThatAreNotArchives)
{
    test::ScratchDir dir;
    const std::string path = dir.path("not.ridge");
    std::ofstream(path)
        << "this is not a terrain archive, but it is long enough to have a header......"
           "...................................................................................";
    try {
        ArchiveReader reader(path);
        FAIL() << "opened a text file";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find(path), std::string::npos);
        EXPECT_NE(std::string(e.what()).find("not a ridge archive"), std::string::npos);
    }
    EXPECT_THROW(ArchiveReader(dir.path("missing.ridge")), Error);
}

// Found by fuzz_archive_reader: a constructor that throws must not leak its descriptor
// (after ~650k rejected files the process could no longer open anything).
TEST(ArchiveReader, RejectingAFileLeaksNoDescriptor)
{
    test::ScratchDir dir;
    const std::string path = dir.path("bad.ridge");
    std::ofstream(path) << std::string(300, 'x');
    auto open_descriptors = [] {
        return std::distance(std::filesystem::directory_iterator("/proc/self/fd"),
                             std::filesystem::directory_iterator());
    };
    const auto before = open_descriptors();
    for (int i = 0; i < 100; ++i)
        EXPECT_THROW(ArchiveReader{path}, Error);
    EXPECT_EQ(open_descriptors(), before);
}
