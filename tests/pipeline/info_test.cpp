// `ridge info --bytes` (issue 31): where an archive's bytes go, by region and by blob part.
#include "test_support.h"

#include "ridge/archive/archive_reader.h"
#include "ridge/pipeline/build.h"
#include "ridge/pipeline/info.h"

#include <gdal.h>
#include <gtest/gtest.h>

#include <filesystem>

using namespace ridge;

TEST(Info, TheByteAccountAddsUpToTheFileAndSplitsEveryBlob)
{
    GDALAllRegister();
    test::ScratchDir dir;
    const std::string out = dir.path("coast.ridge");
    BuildOptions options;
    options.patch_size = 33;
    options.codec = "progressive";
    options.max_error = 1.0;
    buildArchive(test::dataPath("sfbay_coast.tif"), out, options); // a coast: water flags

    EXPECT_FALSE(readArchiveInfo(out).bytes) << "only when asked: it reads every blob";
    const ArchiveInfo info = readArchiveInfo(out, true);
    ASSERT_TRUE(info.bytes);
    const ByteAccount& b = *info.bytes;
    EXPECT_EQ(b.total(), std::filesystem::file_size(out));
    const archive::ArchiveReader reader(out);
    // The index runs from index_offset to the end, packed (format 5) below 48 bytes a patch.
    EXPECT_EQ(b.index, reader.fileSize() - reader.header().index_offset);
    EXPECT_LT(b.index, uint64_t(reader.geometry().patchCount()) * 48);
    EXPECT_EQ(b.metadata, reader.header().metadata_size);
    EXPECT_EQ(b.codec_tables, reader.header().codec_tables_size);
    EXPECT_GT(b.codec_tables, 0u);
    ASSERT_EQ(b.levels.size(), info.levels.size());
    uint64_t flags = 0;
    for (size_t l = 0; l < b.levels.size(); ++l) {
        const ByteAccount::Level& level = b.levels[l];
        // Each level's parts are its blobs, which the index sums too.
        EXPECT_EQ(level.block_errors + level.validity + level.sample_flags + level.payload,
                  info.levels[l].bytes)
            << "level " << l;
        EXPECT_EQ(level.block_errors, 0u) << "derived by readers by default";
        EXPECT_EQ(level.validity, uint64_t(reader.geometry().patchCount(int(l))))
            << "one kind byte a patch: no kept nodata";
        EXPECT_GT(level.payload, 0u);
        flags += level.sample_flags;
    }
    EXPECT_GT(flags, uint64_t(reader.geometry().patchCount())) << "the coast's water bitmaps";
}
