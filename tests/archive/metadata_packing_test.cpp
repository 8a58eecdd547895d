// Format 6 packs the metadata document into one zstd frame coded against a fixed reference
// (archive::metadataReference): the reference is part of the format, pinned here, and the
// frame is hostile input like every region (docs/FORMAT.md, "Metadata").
#include "archive_bytes.h"
#include "archive_craft.h"
#include "fixture_archives.h"
#include "test_support.h"

#include "ridge/archive/archive_metadata.h"
#include "ridge/archive/archive_reader.h"
#include "ridge/archive/format.h"
#include "ridge/core/crc32.h"
#include "ridge/core/error.h"
#include "ridge/pipeline/verify.h"

#include <gtest/gtest.h>
#include <zstd.h>

#include <functional>
#include <string>
#include <vector>

using namespace ridge;
using archive::kFormatVersion;
using test::ArchiveBytes;

namespace {

struct Fixtures {
    test::ScratchDir dir;
    std::string lossless = test::buildEverestArchive(dir, "lossless");
    std::string crafted = dir.path("crafted.ridge");
};

const Fixtures& fixtures()
{
    static const Fixtures f;
    return f;
}

std::string openCrafted(const std::function<void(ArchiveBytes&)>& edit)
{
    return test::openEdited(fixtures().lossless, fixtures().crafted, edit);
}

std::vector<uint8_t> bytesOf(const std::string& s)
{
    return {s.begin(), s.end()};
}

std::string unpack(const std::vector<uint8_t>& region, std::string* json = nullptr)
{
    std::string out;
    const std::string why =
        archive::unpackMetadata(region.data(), region.size(), kFormatVersion, out);
    if (json)
        *json = out;
    return why;
}

// A zstd frame of `text` at level 1 without the reference (valid: the reference is history
// the frame need not use).
std::vector<uint8_t> plainFrame(const std::string& text)
{
    std::vector<uint8_t> frame(ZSTD_compressBound(text.size()));
    frame.resize(ZSTD_compress(frame.data(), frame.size(), text.data(), text.size(), 1));
    return frame;
}

} // namespace

TEST(MetadataPacking, TheReferenceIsPinned)
{
    // Every version 6 archive decodes against these bytes: editing them is a new format.
    const std::string_view reference = archive::metadataReference();
    EXPECT_EQ(reference.size(), 10888u);
    EXPECT_EQ(crc32(reference.data(), reference.size()), 0xc8da09dbu);
    EXPECT_EQ(reference.substr(0, 27), "ridge metadata reference 1:");
}

TEST(MetadataPacking, AGoldenFrameDecodesToItsDocument)
{
    // Packed by ridge when format 6 was made; the frame's matches reach into the reference
    // (the WGS 84 WKT), so it pins the reference's bytes and their use as the prefix.
    const std::vector<uint8_t> golden = {0x28, 0xb5, 0x2f, 0xfd, 0x20, 0xc0, 0x95, 0x00, 0x00,
                                         0x50, 0x7b, 0x0a, 0x5d, 0x22, 0x0a, 0x20, 0x20, 0x7d,
                                         0x0a, 0x7d, 0x01, 0x00, 0xb3, 0x6d, 0x53, 0x10, 0x0b};
    std::string json;
    ASSERT_EQ(unpack(golden, &json), "");
    EXPECT_EQ(json, "{\n  \"generator\": \"ridge 0.1.0\",\n  \"georeference\": {\n    \"crs_wkt\": "
                    "\"GEOGCRS[\\\"WGS 84\\\",ENSEMBLE[\\\"World Geodetic System 1984 ensemble\\\","
                    "MEMBER[\\\"World Geodetic System 1984 (Transit)\\\"]]\"\n  }\n}");
    // Without the reference the same frame does not decode.
    std::string text(json.size(), '\0');
    EXPECT_TRUE(
        ZSTD_isError(ZSTD_decompress(text.data(), text.size(), golden.data(), golden.size())));
}

TEST(MetadataPacking, RoundTripsAndIsAFractionOfTheDocument)
{
    const archive::ArchiveReader reader(fixtures().lossless);
    const std::string& json = reader.metadataJson();
    const std::vector<uint8_t> region = archive::packMetadata(json, kFormatVersion);
    EXPECT_EQ(reader.header().metadata_size, region.size());
    std::string back;
    ASSERT_EQ(unpack(region, &back), "");
    EXPECT_EQ(back, json);
    // The fixture is a WGS 84 source, whose CRS the reference holds: ~2 KB -> ~0.1 KB.
    EXPECT_GT(json.size(), 1500u);
    EXPECT_LT(region.size(), 200u) << region.size() << " bytes for " << json.size();
    // Before version 6 the region is the document itself.
    EXPECT_EQ(archive::packMetadata(json, 5), bytesOf(json));
    std::string raw;
    EXPECT_EQ(archive::unpackMetadata(region.data(), region.size(), 5, raw), "");
    EXPECT_EQ(raw, std::string(region.begin(), region.end()));
}

TEST(MetadataPacking, MalformedFramesAreRefused)
{
    const std::string doc = "{\"generator\": \"x\"}";
    // The document itself where the frame belongs (a version 5 region in a version 6 file).
    EXPECT_EQ(unpack(bytesOf(doc)), "metadata is not a zstd frame that states its content size");
    // A frame that does not state its size: nothing tells how much to allocate.
    std::vector<uint8_t> unsized(ZSTD_compressBound(doc.size()));
    ZSTD_CCtx* cctx = ZSTD_createCCtx();
    ZSTD_CCtx_setParameter(cctx, ZSTD_c_contentSizeFlag, 0);
    unsized.resize(ZSTD_compress2(cctx, unsized.data(), unsized.size(), doc.data(), doc.size()));
    ZSTD_freeCCtx(cctx);
    EXPECT_EQ(unpack(unsized), "metadata is not a zstd frame that states its content size");
    // A 17 MB document of spaces in a few hundred bytes: refused by the size it states, before
    // anything is allocated or decompressed.
    EXPECT_EQ(unpack(plainFrame(std::string(17u << 20, ' '))),
              "metadata frame holds 17825792 bytes: must be 2..16777216");
    EXPECT_EQ(unpack(plainFrame("{")), "metadata frame holds 1 bytes: must be 2..16777216");
    // Bytes after the frame, a second frame, a truncated frame.
    std::vector<uint8_t> frame = archive::packMetadata(doc, kFormatVersion);
    std::vector<uint8_t> trailing = frame;
    trailing.push_back(0);
    EXPECT_EQ(unpack(trailing), "metadata is not exactly one zstd frame (" +
                                    std::to_string(trailing.size()) + " bytes at metadata_offset)");
    std::vector<uint8_t> two = frame;
    two.insert(two.end(), frame.begin(), frame.end());
    EXPECT_NE(unpack(two).find("not exactly one zstd frame"), std::string::npos);
    std::vector<uint8_t> cut(frame.begin(), frame.end() - 1);
    EXPECT_NE(unpack(cut).find("not exactly one zstd frame"), std::string::npos);
    // A frame whose blocks decode to fewer bytes than it states.
    const std::vector<uint8_t> short_frame = plainFrame(doc);
    std::vector<uint8_t> lying = plainFrame(doc + " ");
    const std::vector<uint8_t> body(short_frame.begin() + 6, short_frame.end());
    lying.resize(6);
    lying.insert(lying.end(), body.begin(), body.end());
    ASSERT_EQ(ZSTD_getFrameContentSize(lying.data(), lying.size()), doc.size() + 1);
    EXPECT_NE(unpack(lying).find("does not decompress to its " + std::to_string(doc.size() + 1) +
                                 " bytes against the metadata reference"),
              std::string::npos)
        << unpack(lying);
}

TEST(MetadataPacking, TheReaderRefusesABadFrameNamingTheArchive)
{
    const std::string& crafted = fixtures().crafted;
    // The document stored as it is, as version 5 stores it.
    std::string message = openCrafted([](ArchiveBytes& a) {
        const std::string json = a.metadata();
        a.setMetadataRegion(bytesOf(json));
    });
    EXPECT_EQ(message, crafted + ": metadata is not a zstd frame that states its content size");
    message = openCrafted(
        [](ArchiveBytes& a) { a.setMetadataRegion(plainFrame(std::string(17u << 20, ' '))); });
    EXPECT_EQ(message, crafted + ": metadata frame holds 17825792 bytes: must be 2..16777216");
    // A frame that packs a document the reader then refuses as JSON: the document's own checks
    // still run on what the frame holds.
    message = openCrafted([](ArchiveBytes& a) { a.setMetadata("{\"generator\": 1}"); });
    EXPECT_NE(message.find(crafted + ": metadata: "), std::string::npos) << message;
}

TEST(MetadataPacking, Version5ArchivesWithTheDocumentAsItIsStillRead)
{
    const archive::ArchiveReader current(fixtures().lossless);
    ASSERT_EQ(current.header().version, kFormatVersion);
    ArchiveBytes v5(fixtures().lossless);
    v5.storeMetadataUnpacked();
    v5.set<uint32_t>(8, 5);
    v5.reseal();
    const std::string path = fixtures().dir.path("v5.ridge");
    v5.save(path);
    const archive::ArchiveReader old(path);
    EXPECT_EQ(old.header().version, 5u);
    EXPECT_EQ(old.metadataJson(), current.metadataJson());
    EXPECT_EQ(old.header().metadata_size, current.metadataJson().size());
    const VerifyReport report = verifyArchive(path, VerifyOptions{});
    EXPECT_TRUE(report.ok()) << (report.problems.empty() ? "" : report.problems.front());
    // A version 5 archive holding a frame is refused: its metadata must be the JSON itself.
    ArchiveBytes framed(fixtures().lossless);
    framed.set<uint32_t>(8, 5);
    framed.reseal();
    framed.save(fixtures().crafted);
    EXPECT_THROW(archive::ArchiveReader{fixtures().crafted}, Error);
}
