// The metadata document parsed once at open (ArchiveReader::metadata): typed fields that
// consumers use instead of re-parsing the JSON with fallbacks.
#include "fixture_archives.h"
#include "test_support.h"

#include "ridge/archive/archive_metadata.h"
#include "ridge/archive/archive_reader.h"
#include "ridge/core/error.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

using namespace ridge;

TEST(ArchiveMetadata, TheReaderExposesWhatTheBuildRecordedWithItsTypes)
{
    test::ScratchDir dir;
    const archive::ArchiveReader reader(test::buildEverestArchive(dir, "progressive"));
    const archive::ArchiveMetadata& m = reader.metadata();
    EXPECT_EQ(m.source.width, 301);
    EXPECT_EQ(m.source.height, 203);
    EXPECT_EQ(m.source.data_type, "Int16");
    EXPECT_NE(m.source.path.find("everest_crop.tif"), std::string::npos);
    EXPECT_TRUE(m.source.exact);
    EXPECT_EQ(m.source.voids_filled, 0);
    EXPECT_GE(m.source.min_metres, 3369.0);
    EXPECT_LE(m.source.max_metres, 8840.0);
    EXPECT_TRUE(m.georeference.geographic);
    EXPECT_NE(m.georeference.crs_wkt.find("WGS 84"), std::string::npos);
    EXPECT_FALSE(m.georeference.spacing_from_user);
    ASSERT_TRUE(m.georeference.geotransform.has_value());
    EXPECT_GT((*m.georeference.geotransform)[1], 0.0); // degrees per pixel east
    EXPECT_LT((*m.georeference.geotransform)[5], 0.0); // north up
    EXPECT_EQ(m.build.patch_size, 33);
    EXPECT_EQ(m.build.block_cells, 8);
    EXPECT_EQ(m.build.codec, "progressive");
    EXPECT_EQ(m.build.filter, "decimate");
    EXPECT_EQ(m.build.z_scale, 1.0);
    EXPECT_EQ(m.build.z_offset, 0.0);
    EXPECT_EQ(m.build.codec_max_error, 2.0);
    EXPECT_FALSE(m.build.max_error.has_value());
    EXPECT_TRUE(m.build.codec_variant.has_value());
    EXPECT_EQ(m.generator.rfind("ridge ", 0), 0u);
}

TEST(ArchiveMetadata, ParsingChecksAgainstTheHeaderItIsGiven)
{
    test::ScratchDir dir;
    const archive::ArchiveReader reader(test::buildEverestArchive(dir, "lossless"));
    archive::Header other = reader.header();
    EXPECT_NO_THROW(archive::parseArchiveMetadata(reader.metadataJson(), other));
    other.width = 300;
    try {
        archive::parseArchiveMetadata(reader.metadataJson(), other);
        ADD_FAILURE() << "a width that differs from the header's was accepted";
    } catch (const Error& e) {
        EXPECT_EQ(std::string(e.what()),
                  "metadata: source.width is 301 but the header's width is 300");
    }
}

// build.vertical_shift (heights shifted from a geoid to the ellipsoid): parsed with its
// types, refused by field when a value is out of range.
TEST(ArchiveMetadata, VerticalShiftIsParsedAndChecked)
{
    test::ScratchDir dir;
    const archive::ArchiveReader reader(test::buildEverestArchive(dir, "lossless"));
    EXPECT_FALSE(reader.metadata().build.vertical_shift.has_value());
    nlohmann::json j = nlohmann::json::parse(reader.metadataJson());
    const auto parse = [&] { return archive::parseArchiveMetadata(j.dump(), reader.header()); };
    j["build"]["vertical_shift"] = {
        {"from", "EGM96 height"}, {"from_epsg", 5773}, {"operation", "WGS 84 to EGM96 height"}};
    const archive::ArchiveMetadata m = parse();
    ASSERT_TRUE(m.build.vertical_shift.has_value());
    EXPECT_EQ(m.build.vertical_shift->from, "EGM96 height");
    EXPECT_EQ(m.build.vertical_shift->from_epsg, 5773);
    EXPECT_EQ(m.build.vertical_shift->operation, "WGS 84 to EGM96 height");

    const auto refusal = [&] {
        try {
            parse();
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string("accepted");
    };
    j["build"]["vertical_shift"]["from_epsg"] = 0;
    EXPECT_NE(refusal().find("build.vertical_shift.from_epsg is 0"), std::string::npos)
        << refusal();
    j["build"]["vertical_shift"]["from_epsg"] = 5773;
    j["build"]["vertical_shift"]["from"] = "";
    EXPECT_NE(refusal().find("build.vertical_shift.from is \"\""), std::string::npos) << refusal();
    j["build"]["vertical_shift"] = "EGM96";
    EXPECT_NE(refusal().find("build.vertical_shift"), std::string::npos) << refusal();
}
