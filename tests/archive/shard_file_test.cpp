// The shard file container (archive/shard_file.h): golden bytes of a small file, and every
// header and directory field refused when it is wrong.
#include "ridge/archive/shard_file.h"
#include "ridge/core/crc32.h"
#include "ridge/core/error.h"

#include "test_support.h"

#include <gtest/gtest.h>

#include <cstring>
#include <fstream>

namespace ridge::archive {
namespace {

std::string write(const test::ScratchDir& dir)
{
    const std::string path = dir.path("f.shard");
    ShardFileWriter out(path, {ShardFileKind::Segment, 0x1122334455667788ull, 5, 0xabcdefull});
    out.addSection(shardTag("INFO"), std::vector<uint8_t>{'{', '}'});
    out.beginSection(shardTag("BLOB"));
    out.append("xyz", 3);
    out.endSection();
    out.finish();
    return path;
}

void put(std::string& bytes, size_t at, uint64_t v, int n)
{
    for (int b = 0; b < n; ++b)
        bytes[at + b] = char(v >> (8 * b));
}

// `bytes` with the header CRC (and, when `directory`, the directory CRC) made right again,
// so that the field under test is what the reader refuses.
std::string resealed(std::string bytes, bool directory)
{
    if (directory) {
        const uint64_t offset = uint64_t(uint8_t(bytes[48])) | uint64_t(uint8_t(bytes[49])) << 8;
        put(bytes, 56, crc32(bytes.data() + offset, bytes.size() - offset), 4);
    }
    put(bytes, 60, crc32(bytes.data(), 60), 4);
    return bytes;
}

std::string refusal(const test::ScratchDir& dir, const std::string& bytes)
{
    const std::string path = dir.path("bad.shard");
    std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
    try {
        ShardFileReader reader(path);
        reader.read(shardTag("INFO"), 100);
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

TEST(ShardFile, BytesArePinned)
{
    const test::ScratchDir dir;
    const std::string bytes = test::readFile(write(dir));
    // Header, INFO "{}", BLOB "xyz", two 32-byte directory entries.
    ASSERT_EQ(bytes.size(), 64u + 2 + 3 + 64);
    EXPECT_EQ(bytes.substr(0, 8), "RIDGESHD");
    const uint8_t head[] = {1, 0, 0, 0, 4, 0, 0, 0, 0x88, 0x77, 0x66, 0x55, 0x44, 0x33, 0x22, 0x11,
                            5, 0, 0, 0, 0, 0, 0, 0, 0xef, 0xcd, 0xab, 0,    0,    0,    0,    0,
                            2, 0, 0, 0, 0, 0, 0, 0, 69,   0,    0,    0,    0,    0,    0,    0};
    EXPECT_EQ(std::memcmp(bytes.data() + 8, head, sizeof head), 0);
    const uint8_t info_entry[] = {'I', 'N', 'F', 'O', 1, 0, 0, 0};
    EXPECT_EQ(std::memcmp(bytes.data() + 69, info_entry, sizeof info_entry), 0);
    EXPECT_EQ(uint8_t(bytes[69 + 16]), 64); // INFO at 64, 2 bytes
    EXPECT_EQ(uint8_t(bytes[69 + 24]), 2);
    const uint8_t blob_entry[] = {'B', 'L', 'O', 'B', 0, 0, 0, 0, 0, 0, 0, 0};
    EXPECT_EQ(std::memcmp(bytes.data() + 101, blob_entry, sizeof blob_entry), 0);
    EXPECT_EQ(uint8_t(bytes[101 + 16]), 66);
    EXPECT_EQ(uint8_t(bytes[101 + 24]), 3);

    const ShardFileReader reader(dir.path("f.shard"));
    EXPECT_EQ(reader.header().kind, ShardFileKind::Segment);
    EXPECT_EQ(reader.header().shard, 5);
    EXPECT_EQ(reader.read(shardTag("INFO"), 10), (std::vector<uint8_t>{'{', '}'}));
    char blob[3];
    reader.readAt(shardTag("BLOB"), 0, blob, 3);
    EXPECT_EQ(std::string(blob, 3), "xyz");
    EXPECT_THROW(reader.read(shardTag("BLOB"), 10), Error); // no section CRC to check
    EXPECT_THROW(reader.readAt(shardTag("BLOB"), 1, blob, 3), Error);
    EXPECT_THROW(reader.read(shardTag("INFO"), 1), Error); // larger than allowed
    EXPECT_THROW(reader.read(shardTag("NONE"), 10), Error);
    EXPECT_NO_THROW(reader.expect(ShardFileKind::Segment, 0x1122334455667788ull, 5));
    EXPECT_THROW(reader.expect(ShardFileKind::Segment, 0x1122334455667788ull, 4), Error);
    EXPECT_THROW(reader.expect(ShardFileKind::Summary, 0x1122334455667788ull, 5), Error);
    EXPECT_THROW(reader.expect(ShardFileKind::Segment, 1, 5), Error);
    EXPECT_TRUE(shardFileMatches(dir.path("f.shard"),
                                 {ShardFileKind::Segment, 0x1122334455667788ull, 5, 0xabcdef}));
    EXPECT_FALSE(shardFileMatches(dir.path("f.shard"),
                                  {ShardFileKind::Segment, 0x1122334455667788ull, 5, 0xabcdee}));
    EXPECT_FALSE(shardFileMatches(dir.path("absent"), {}));
}

TEST(ShardFile, EveryFieldIsValidated)
{
    const test::ScratchDir dir;
    const std::string good = test::readFile(write(dir));
    ASSERT_EQ(refusal(dir, good), "");
    auto edited = [&](size_t at, uint64_t v, int n, bool directory = false) {
        std::string b = good;
        put(b, at, v, n);
        return refusal(dir, resealed(b, directory));
    };
    auto expectRefused = [](const std::string& message, const std::string& what) {
        EXPECT_NE(message.find(what), std::string::npos) << message;
    };
    expectRefused(refusal(dir, "RIDGESHD"), "shorter than the 64-byte header");
    expectRefused(edited(0, 'X', 1), "does not start with RIDGESHD");
    std::string crc = good;
    crc[20] ^= 1;
    expectRefused(refusal(dir, crc), "header CRC-32 mismatch");
    expectRefused(edited(8, 2, 4), "version 2");
    expectRefused(edited(12, 9, 4), "kind 9");
    expectRefused(edited(40, 65, 4), "65 sections");
    expectRefused(edited(44, 1, 4), "reserved header bytes");
    expectRefused(refusal(dir, good.substr(0, good.size() - 1)), "does not end the file");
    expectRefused(refusal(dir, good + "x"), "does not end the file");
    std::string dir_crc = good;
    dir_crc[69 + 20] ^= 1;
    expectRefused(refusal(dir, dir_crc), "directory CRC-32 mismatch");
    expectRefused(edited(69 + 16, 200, 8, true), "lies outside the data");
    expectRefused(edited(69 + 4, 3, 4, true), "unknown flags");
    expectRefused(edited(101 + 12, 1, 4, true), "reserved bytes");
    expectRefused(edited(101, shardTag("INFO"), 4, true), "INFO twice");
    expectRefused(edited(101 + 16, 65, 8, true), "overlap");
    std::string data = good;
    data[64] = '[';
    expectRefused(refusal(dir, data), "section INFO CRC-32 mismatch");
}

} // namespace
} // namespace ridge::archive
