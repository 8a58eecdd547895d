// End-to-end: ingest -> build -> read back -> verify, on the real fixtures.
#include "test_support.h"

#include "ridge/archive/archive_reader.h"
#include "ridge/codec/codec_registry.h"
#include "ridge/core/crc32.h"
#include "ridge/core/error.h"
#include "ridge/pipeline/build.h"
#include "ridge/pipeline/build_memory.h"
#include "ridge/pipeline/level_decoder.h"
#include "ridge/pipeline/verify.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

using namespace ridge;

namespace {

BuildOptions smallPatches(int patch = 33)
{
    BuildOptions o;
    o.patch_size = patch;
    return o;
}

std::vector<uint8_t> readFile(const std::string& path)
{
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
}

void writeFile(const std::string& path, const std::vector<uint8_t>& bytes)
{
    std::ofstream(path, std::ios::binary)
        .write(reinterpret_cast<const char*>(bytes.data()), bytes.size());
}

} // namespace

TEST(BuildVerify, IntegerInputRoundTripsExactlyAndEveryBoundHolds)
{
    test::ScratchDir dir;
    const std::string source = test::dataPath("everest_crop.tif");
    const std::string out = dir.path("everest.ridge");
    const BuildReport report = buildArchive(source, out, smallPatches());
    EXPECT_EQ(report.quantization_error, 0.0);

    const io::ElevationRaster raster = io::ingestRaster(source);
    const archive::ArchiveReader reader(out);
    const CodeGrid finest = decodeLevel(reader, reader.geometry().finestLevel());
    ASSERT_EQ(finest.width, raster.grid.width);
    ASSERT_EQ(finest.height, raster.grid.height);
    EXPECT_EQ(finest.codes, raster.grid.codes); // bit-exact

    VerifyOptions options;
    options.source = source;
    const VerifyReport v = verifyArchive(out, options);
    ASSERT_TRUE(v.ok()) << v.problems.front();
    ASSERT_TRUE(v.source_checked);
    EXPECT_EQ(v.levels.back().max_error, 0.0);
    EXPECT_EQ(v.levels.back().samples, int64_t{raster.grid.width} * raster.grid.height);
    for (const LevelVerifyReport& l : v.levels) {
        EXPECT_EQ(l.bound_violations, 0);
        EXPECT_LE(l.max_error, l.max_err_bound + 1e-9);
    }
    EXPECT_GT(v.levels.front().max_error, 100.0); // a coarse level of Everest is far off
}

TEST(BuildVerify, VoidsAreFilledAndNonPowerOfTwoGridsWork)
{
    test::ScratchDir dir;
    const std::string source = test::dataPath("rainier_voids.tif");
    const std::string out = dir.path("rainier.ridge");
    for (int patch : {17, 65, 129}) {
        const BuildReport report = buildArchive(source, out, smallPatches(patch));
        EXPECT_GT(report.voids_filled, 200);
        VerifyOptions options;
        options.source = source;
        const VerifyReport v = verifyArchive(out, options);
        ASSERT_TRUE(v.ok()) << v.problems.front();
        EXPECT_EQ(v.source_voids, report.voids_filled);
    }
}

TEST(BuildVerify, NevilleFilterBoundsHoldEndToEnd)
{
    test::ScratchDir dir;
    const std::string source = test::dataPath("everest_crop.tif");
    const std::string out = dir.path("neville.ridge");
    BuildOptions o = smallPatches();
    o.filter = PyramidFilter::Neville4;
    buildArchive(source, out, o);
    VerifyOptions options;
    options.source = source;
    const VerifyReport v = verifyArchive(out, options);
    ASSERT_TRUE(v.ok()) << v.problems.front();
    EXPECT_EQ(v.levels.back().max_error, 0.0);
}

TEST(BuildVerify, RandomAccessReadsOnePatchWithoutTheOthers)
{
    test::ScratchDir dir;
    const std::string out = dir.path("a.ridge");
    buildArchive(test::dataPath("everest_crop.tif"), out, smallPatches());
    // Destroy every patch but one: that one must still decode.
    const archive::ArchiveReader reader(out);
    const PatchId keep{reader.geometry().finestLevel(), 1, 1};
    std::vector<uint8_t> bytes = readFile(out);
    for (const archive::PatchRecord& r : reader.index())
        if (PatchId{int(r.level), int(r.x), int(r.y)} != keep)
            std::fill_n(bytes.begin() + r.offset, r.size, 0xee);
    writeFile(out, bytes);
    const archive::ArchiveReader damaged(out);
    std::vector<uint16_t> codes(33 * 33);
    EXPECT_NO_THROW(damaged.decodePatch(keep, codes.data()));
    EXPECT_THROW(damaged.decodePatch({keep.level, 0, 0}, codes.data()), Error);
}

// A flipped byte anywhere in the file is caught; inside a patch blob, by that patch's name.
TEST(BuildVerify, FlippedByteAnywhereIsReportedWithThePatchItHits)
{
    test::ScratchDir dir;
    const std::string good = dir.path("good.ridge");
    const std::string bad = dir.path("bad.ridge");
    buildArchive(test::dataPath("everest_crop.tif"), good, smallPatches(65));
    const std::vector<uint8_t> bytes = readFile(good);
    const archive::ArchiveReader reader(good);
    const archive::Header& h = reader.header();

    // Every header byte, strides through metadata and index (they fail at open, cheaply), and
    // the first, middle and last byte of every patch blob (each costs a full verify).
    std::vector<size_t> positions;
    for (size_t i = 0; i < archive::kHeaderSize; ++i)
        positions.push_back(i);
    for (size_t i = h.metadata_offset; i < h.metadata_offset + h.metadata_size; i += 13)
        positions.push_back(i);
    for (size_t i = h.index_offset; i < bytes.size(); i += 7)
        positions.push_back(i);
    positions.push_back(bytes.size() - 1);
    for (const archive::PatchRecord& r : reader.index())
        for (size_t i : {r.offset, r.offset + r.size / 2, r.offset + r.size - 1})
            positions.push_back(i);

    for (size_t pos : positions) {
        std::vector<uint8_t> flipped = bytes;
        flipped[pos] ^= 0x01;
        writeFile(bad, flipped);
        const VerifyReport v = verifyArchive(bad, {});
        ASSERT_FALSE(v.ok()) << "flip at byte " << pos << " went unnoticed";
        const std::string& problem = v.problems.front();
        EXPECT_NE(problem.find(bad), std::string::npos);
        if (pos >= archive::kHeaderSize && pos < h.metadata_offset) {
            const auto hit =
                std::find_if(reader.index().begin(), reader.index().end(), [&](const auto& r) {
                    return pos >= r.offset && pos < r.offset + r.size;
                });
            ASSERT_NE(hit, reader.index().end());
            const std::string name =
                archive::ArchiveReader::patchName({int(hit->level), int(hit->x), int(hit->y)});
            EXPECT_NE(problem.find(name), std::string::npos) << problem;
            EXPECT_EQ(v.problems.size(), 1u) << "one flipped byte hits one patch";
        }
    }
}

TEST(BuildVerify, TruncatedArchivesAreRejected)
{
    test::ScratchDir dir;
    const std::string good = dir.path("good.ridge");
    buildArchive(test::dataPath("everest_crop.tif"), good, smallPatches(65));
    const std::vector<uint8_t> bytes = readFile(good);
    for (size_t keep : {size_t{0}, size_t{100}, size_t{200}, bytes.size() / 2, bytes.size() - 1}) {
        const std::string cut = dir.path("cut.ridge");
        writeFile(cut, std::vector<uint8_t>(bytes.begin(), bytes.begin() + keep));
        EXPECT_FALSE(verifyArchive(cut, {}).ok()) << keep;
    }
}

TEST(BuildVerify, VerifyCatchesASourceThatDoesNotMatch)
{
    test::ScratchDir dir;
    const std::string out = dir.path("everest.ridge");
    buildArchive(test::dataPath("everest_crop.tif"), out, smallPatches());
    VerifyOptions options;
    options.source = test::dataPath("rainier_voids.tif");
    EXPECT_FALSE(verifyArchive(out, options).ok());
}

TEST(Build, CancellingLeavesNoOutput)
{
    test::ScratchDir dir;
    const std::string out = dir.path("cancelled.ridge");
    BuildOptions o = smallPatches(17);
    o.progress = [](double f) { return f < 0.6; };
    EXPECT_THROW(buildArchive(test::dataPath("everest_crop.tif"), out, o), Cancelled);
    for (const auto& entry : std::filesystem::directory_iterator(dir.dir()))
        ADD_FAILURE() << "left behind: " << entry.path();
}

TEST(Build, RejectsBadPatchAndBlockSizesBeforeWritingAnything)
{
    test::ScratchDir dir;
    const std::string out = dir.path("x.ridge");
    BuildOptions o;
    o.patch_size = 100;
    EXPECT_THROW(buildArchive(test::dataPath("everest_crop.tif"), out, o), Error);
    o.patch_size = 129;
    o.block_cells = 12;
    EXPECT_THROW(buildArchive(test::dataPath("everest_crop.tif"), out, o), Error);
    EXPECT_FALSE(std::filesystem::exists(out));
}

// The streaming build (finest level strip by strip) must produce exactly the patches and
// bounds of the in-memory build, for every codec that streams (a learning codec included: it
// trains over passes of strips on what the in-memory build trains on); only the blob order in
// the file differs.
TEST(Build, StreamingAndInMemoryBuildsAgreePatchForPatch)
{
    test::ScratchDir dir;
    const std::string source = test::dataPath("everest_crop.tif");
    int codecs = 0;
    for (const CodecInfo& codec : codecRegistry()) {
        BuildOptions options = smallPatches();
        options.codec = codec.name;
        if (codec.lossy)
            options.max_error = 2.0;
        if (!buildStreams(options))
            continue;
        ++codecs;
        for (int patch : {17, 65}) {
            SCOPED_TRACE(std::string(codec.name) + ", patch " + std::to_string(patch));
            options.patch_size = patch;
            const std::string streamed = dir.path("streamed.ridge");
            const std::string in_memory = dir.path("in_memory.ridge");
            const BuildReport s = buildArchive(source, streamed, options);
            EXPECT_TRUE(s.streamed);
            const BuildReport m = buildArchive(io::ingestRaster(source), in_memory, options);
            EXPECT_FALSE(m.streamed);

            const archive::ArchiveReader a(streamed), b(in_memory);
            EXPECT_EQ(a.header().codec_tables_size, b.header().codec_tables_size);
            EXPECT_EQ(a.header().codec_tables_crc32, b.header().codec_tables_crc32);
            ASSERT_EQ(a.index().size(), b.index().size());
            const int n = a.geometry().patchSize();
            std::vector<uint16_t> pa(n * n), pb(n * n);
            for (size_t i = 0; i < a.index().size(); ++i) {
                const archive::PatchRecord& ra = a.index()[i];
                const archive::PatchRecord& rb = b.index()[i];
                const PatchId p{int(ra.level), int(ra.x), int(ra.y)};
                EXPECT_EQ(ra.min_height, rb.min_height) << i;
                EXPECT_EQ(ra.max_height, rb.max_height) << i;
                EXPECT_EQ(ra.err_appr, rb.err_appr) << i;
                EXPECT_EQ(ra.err, rb.err) << i;
                ASSERT_EQ(a.readBlob(p), b.readBlob(p)) << i;
                a.decodePatch(p, pa.data());
                b.decodePatch(p, pb.data());
                ASSERT_EQ(pa, pb) << i;
                EXPECT_EQ(a.readBlockErrors(p), b.readBlockErrors(p)) << i;
            }
        }
    }
    EXPECT_GE(codecs, 3); // raw, lossless, progressive
}

TEST(Build, SourcesWithVoidsFallBackToTheInMemoryPathAndFillThem)
{
    test::ScratchDir dir;
    const BuildReport r =
        buildArchive(test::dataPath("rainier_voids.tif"), dir.path("r.ridge"), smallPatches());
    EXPECT_FALSE(r.streamed);
    EXPECT_EQ(r.voids_filled, 368);
}

// A bound that is too small, in an otherwise valid archive (checksums recomputed), must be
// caught by verify --source: the check can fail.
TEST(BuildVerify, SourceCheckCatchesAnUnderstatedErrorBound)
{
    test::ScratchDir dir;
    const std::string source = test::dataPath("everest_crop.tif");
    const std::string out = dir.path("lying.ridge");
    buildArchive(source, out, smallPatches());
    std::vector<uint8_t> bytes = readFile(out);
    archive::Header header;
    ASSERT_EQ(archive::parseHeader(bytes.data(), header), "");

    // Claim 1 m for Err_Appr and Err of the level-3 patch (3, 0, 0), consistently, re-signed.
    const archive::ArchiveReader reader(out);
    const int64_t index = reader.geometry().patchIndex({3, 0, 0});
    const uint64_t count = uint64_t(reader.geometry().patchCount());
    std::vector<uint8_t> entries;
    ASSERT_EQ(archive::unpackIndex(bytes.data() + header.index_offset,
                                   bytes.size() - header.index_offset, count, header.version,
                                   entries),
              "");
    std::vector<archive::PatchRecord> records(count);
    for (uint64_t i = 0; i < count; ++i)
        records[i] = archive::parseRecord(entries.data() + i * archive::kIndexEntrySize);
    archive::PatchRecord& r = records[size_t(index)];
    ASSERT_GT(r.err, 10.f);
    r.err = 1.f;
    r.err_appr = 1.f;
    const std::vector<uint8_t> packed = archive::packIndex(records, header.version);
    bytes.resize(header.index_offset);
    bytes.insert(bytes.end(), packed.begin(), packed.end());
    header.index_crc32 =
        crc32(bytes.data() + header.index_offset, bytes.size() - header.index_offset);
    archive::serializeHeader(header, bytes.data());
    writeFile(out, bytes);

    // Without the source too (issue 23): Err_Int measured on the decoded levels exceeds 1 m.
    const VerifyReport plain = verifyArchive(out, {});
    ASSERT_FALSE(plain.ok());
    EXPECT_NE(plain.problems.front().find("patch (level 3, x 0, y 0): stored Err_Appr 1 m is below "
                                          "Err_Int"),
              std::string::npos)
        << plain.problems.front();
    VerifyOptions options;
    options.source = source;
    const VerifyReport v = verifyArchive(out, options);
    ASSERT_FALSE(v.ok());
    ASSERT_EQ(v.levels.size(), size_t(reader.geometry().levelCount())) << v.problems.front();
    EXPECT_GT(v.levels[3].bound_violations, 0);
    EXPECT_EQ(v.levels[4].bound_violations, 0);
    EXPECT_NE(v.problems.front().find("level 3"), std::string::npos) << v.problems.front();
}
