// The second hostile-input review (issue 23) against the reader's regions: a metadata value
// nested 100,000 deep (which crashed every command through a recursive dump), metadata with
// bytes after a NUL, a geotransform no command can use, codec tables on codecs that have none,
// sizes beyond what any archive needs, bytes after a JPEG 2000 codestream's end, and the
// writer, which must not write what the reader refuses. Each archive is a real one with one
// thing changed and every checksum recomputed, so only the checks named here can refuse it.
#include "archive_bytes.h"
#include "archive_craft.h"
#include "fixture_archives.h"
#include "test_support.h"

#include "ridge/archive/archive_metadata.h"
#include "ridge/archive/archive_reader.h"
#include "ridge/archive/archive_writer.h"
#include "ridge/core/error.h"
#include "ridge/pipeline/build.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <functional>
#include <string>

using namespace ridge;
using test::ArchiveBytes;
namespace ho = test::header_offset;
namespace eo = test::entry_offset;

namespace {

struct Fixtures {
    test::ScratchDir dir;
    std::string lossless = test::buildEverestArchive(dir, "lossless");
    std::string raw = test::buildEverestArchive(dir, "raw");
    std::string progressive = test::buildEverestArchive(dir, "progressive");
    std::string jpeg2000 = test::buildEverestArchive(dir, "jpeg2000");
    std::string crafted = dir.path("crafted.ridge");
};

const Fixtures& fixtures()
{
    static const Fixtures f;
    return f;
}

// The fixture `archive` edited, resealed and opened: the reader's message, "" if it opened.
std::string openCrafted(const std::string& archive, const std::function<void(ArchiveBytes&)>& edit)
{
    return test::openEdited(archive, fixtures().crafted, edit);
}

// The metadata with `generator` replaced by the JSON text `value`.
std::function<void(ArchiveBytes&)> generatorText(const std::string& value)
{
    return [value](ArchiveBytes& a) {
        nlohmann::json j = nlohmann::json::parse(a.metadata());
        j["generator"] = "@";
        std::string text = j.dump();
        text.replace(text.find("\"@\""), 3, value);
        a.setMetadata(text);
    };
}

std::string nested(int depth, const std::string& inner = "")
{
    return std::string(static_cast<size_t>(depth), '[') + inner +
           std::string(static_cast<size_t>(depth), ']');
}

void expectRefused(const std::string& message, const std::string& phrase)
{
    EXPECT_EQ(message.rfind(fixtures().crafted + ": ", 0), 0u) << message;
    EXPECT_NE(message.find(phrase), std::string::npos)
        << "expected '" << phrase << "' in: " << message;
}

} // namespace

TEST(HostileRegions, AMetadataValueNestedWithoutLimitIsRefusedBeforeAnythingSerialisesIt)
{
    // 100,000 nested arrays crashed (SIGSEGV) in the recursive dump of the error message.
    expectRefused(openCrafted(fixtures().lossless, generatorText(nested(100000))),
                  "metadata: values nested more than 32 deep");
    // Within the limit the document parses, and the wrong type is quoted in at most 40 bytes
    // however long the value: a 1 MB string inside 31 arrays.
    const std::string message = openCrafted(
        fixtures().lossless, generatorText(nested(31, "\"" + std::string(1 << 20, 'x') + "\"")));
    expectRefused(message, "metadata: generator is [[[[");
    EXPECT_NE(message.find("...: must be a string"), std::string::npos) << message;
    EXPECT_LT(message.size(), fixtures().crafted.size() + 120) << message;
    // 32 levels (the document itself and 31 inside it) are the most the format allows.
    expectRefused(openCrafted(fixtures().lossless, generatorText(nested(32))),
                  "metadata: values nested more than 32 deep");
}

TEST(HostileRegions, AQuotedStringIsCutOnACharacterBoundary)
{
    // Messages end up in `verify --json`: a cut through a UTF-8 sequence would make them
    // invalid UTF-8 there. "é" is two bytes: after [\"xx byte 37 falls inside one.
    std::string value = "\"xx";
    for (int k = 0; k < 30; ++k)
        value += "\xc3\xa9";
    value += "\"";
    const std::string message = openCrafted(fixtures().lossless, generatorText("[" + value + "]"));
    expectRefused(message, "must be a string");
    EXPECT_NO_THROW((void)nlohmann::json(message).dump()) << "the message is not UTF-8";
}

TEST(HostileRegions, MetadataWithBytesAfterANulIsRefused)
{
    // nlohmann's parser takes a NUL for the end of the text: valid JSON, a NUL and anything
    // after it opened, hiding bytes in a checksummed region nobody reads.
    const std::string message = openCrafted(fixtures().lossless, [](ArchiveBytes& a) {
        a.setMetadata(a.metadata() + std::string("\0hidden bytes", 13));
    });
    expectRefused(message, "metadata: not JSON: a NUL byte at offset");
}

TEST(HostileRegions, AGeotransformNoCommandCanUseIsRefusedAtOpen)
{
    // All zeros: verify said OK, extract wrote a GeoTIFF with pixels of size 0, info and query
    // refused. Every command opens through the reader, so all refuse it now.
    auto withGeotransform = [](nlohmann::json gt) {
        return [gt](ArchiveBytes& a) {
            nlohmann::json j = nlohmann::json::parse(a.metadata());
            j["georeference"]["geotransform"] = gt;
            a.setMetadata(j.dump());
        };
    };
    expectRefused(openCrafted(fixtures().lossless, withGeotransform({0, 0, 0, 0, 0, 0})),
                  "metadata: georeference.geotransform is [0,0,0,0,0,0]: its pixels have zero "
                  "area");
    // Collinear pixel vectors: also no inverse.
    expectRefused(openCrafted(fixtures().lossless, withGeotransform({0, 1, 2, 0, 2, 4})),
                  "its pixels have zero area (determinant 0)");
    // An inverse that overflows, and corners beyond f64.
    expectRefused(openCrafted(fixtures().lossless, withGeotransform({0, 1e-200, 0, 0, 0, -1e-200})),
                  "zero area");
    expectRefused(openCrafted(fixtures().lossless, withGeotransform({1e308, 1e306, 0, 0, 0, -1})),
                  "the grid's corners are not finite");
    // A rotated but invertible one is fine.
    EXPECT_EQ(openCrafted(fixtures().lossless, withGeotransform({10, 1, 0.5, 20, 0.25, -1})), "");
}

TEST(HostileRegions, CodecTablesOnACodecWithoutTablesAreRefused)
{
    // The format allows tables only for progressive v2; raw and lossless accepted arbitrary
    // bytes there, and even a real progressive table.
    const std::vector<uint8_t> junk = {'T', 1, 5, 0, 1, 2, 3};
    for (const std::string* archive : {&fixtures().lossless, &fixtures().raw}) {
        const std::string message =
            openCrafted(*archive, [&](ArchiveBytes& a) { test::setCodecTables(a, junk); });
        expectRefused(message, "codec tables region of 7 bytes: the ");
        EXPECT_NE(message.find("codec has no codec tables"), std::string::npos) << message;
    }
    ArchiveBytes progressive(fixtures().progressive);
    const uint64_t at = progressive.get<uint64_t>(test::codec_tables_offset::kOffset);
    const uint32_t size = progressive.get<uint32_t>(test::codec_tables_offset::kSize);
    if (size > 0) {
        const std::vector<uint8_t> real(progressive.bytes().begin() + std::ptrdiff_t(at),
                                        progressive.bytes().begin() + std::ptrdiff_t(at + size));
        expectRefused(openCrafted(fixtures().lossless,
                                  [&](ArchiveBytes& a) { test::setCodecTables(a, real); }),
                      "the lossless codec has no codec tables");
    }
    // jpeg2000 refuses them too (its own parameter check), and an empty region stays valid.
    expectRefused(
        openCrafted(fixtures().jpeg2000, [&](ArchiveBytes& a) { test::setCodecTables(a, junk); }),
        "codec tables are present: the jpeg2000 codec has none");
    EXPECT_EQ(
        openCrafted(fixtures().lossless, [](ArchiveBytes& a) { test::setCodecTables(a, {}); }), "");
}

TEST(HostileRegions, RegionSizesBeyondAnyArchivesAreRefusedBeforeTheyAreRead)
{
    // A 17 MB metadata region: no archive needs it; refused by its size field before 17 MB
    // are allocated and read.
    const std::string message = openCrafted(fixtures().lossless, [](ArchiveBytes& a) {
        std::vector<uint8_t> region = a.metadataRegion();
        region.resize(17u << 20, ' ');
        a.setMetadataRegion(region);
    });
    expectRefused(message, "header field metadata_size is 17825792: must be at most 16777216");
    // A codec tables region larger than any codec's tables.
    expectRefused(openCrafted(fixtures().progressive,
                              [](ArchiveBytes& a) {
                                  test::setCodecTables(a, std::vector<uint8_t>((1u << 20) + 1, 0));
                              }),
                  "header field codec_tables_size is 1048577: must be at most 1048576");
}

TEST(HostileRegions, BytesAfterAJpeg2000CodestreamsEndAreRefused)
{
    // Neither library notices bytes after the EOC marker; the progressive codecs refuse
    // trailing bytes, and so does jpeg2000 now. Also a tile-part whose Psot is 0.
    ArchiveBytes bytes(fixtures().jpeg2000);
    const archive::ArchiveReader original(fixtures().jpeg2000);
    const PatchId root{0, 0, 0};
    const archive::PatchRecord& r = original.record(root);
    const std::vector<uint8_t> blob = test::blobOf(bytes, 0);
    test::replaceBlobBytes(bytes, 0, r.size, r.size, {0xFF, 0xD9, 0x00, 0x2A});
    bytes.reseal();
    bytes.save(fixtures().crafted);
    const archive::ArchiveReader reader(fixtures().crafted);
    std::vector<uint16_t> codes(33 * 33);
    try {
        reader.decodePatch(root, codes.data());
        ADD_FAILURE() << "bytes after the EOC decoded";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("patch (level 0, x 0, y 0): cannot decode: trailing "
                                             "bytes after payload"),
                  std::string::npos)
            << e.what();
    }
    // Psot = 0 ("to the EOC") would let such bytes pass as tile data: refused.
    const size_t payload = original.payloadOffset(root, blob);
    const size_t border = size_t(blob[payload + 13]) | size_t(blob[payload + 14]) << 8 |
                          size_t(blob[payload + 15]) << 16 | size_t(blob[payload + 16]) << 24;
    size_t sot = payload + 17 + border;
    while (!(blob[sot] == 0xFF && blob[sot + 1] == 0x90))
        ++sot;
    ArchiveBytes zero(fixtures().jpeg2000);
    test::replaceBlobBytes(zero, 0, sot + 6, sot + 10, {0, 0, 0, 0});
    zero.reseal();
    zero.save(fixtures().crafted);
    try {
        archive::ArchiveReader(fixtures().crafted).decodePatch(root, codes.data());
        ADD_FAILURE() << "Psot 0 decoded";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("cannot decode: corrupt payload"), std::string::npos)
            << e.what();
    }
}

TEST(HostileRegions, TheWriterRefusesMetadataTheReaderWouldRefuseAndLeavesNothing)
{
    // What a reader refuses is never written: the archive writer checks its metadata with
    // the reader's parser (a source whose geotransform has zero-area pixels, say).
    const archive::ArchiveReader source(fixtures().lossless);
    nlohmann::json j = nlohmann::json::parse(source.metadataJson());
    j["georeference"]["geotransform"] = {0, 0, 0, 0, 0, 0};
    const std::string out = fixtures().dir.path("written.ridge");
    {
        archive::ArchiveWriter writer(out, source.header());
        const PyramidGeometry& g = source.geometry();
        for (int64_t i = 0; i < g.patchCount(); ++i) {
            const PatchId p = g.patchAt(i);
            std::vector<uint8_t> blob = source.readBlob(p);
            const size_t payload = source.payloadOffset(p, blob);
            // The fixture has no nodata and derives its block errors: the all-valid form.
            writer.writePatch(source.record(p), {}, blob.data() + payload, blob.size() - payload);
        }
        try {
            writer.finish(j.dump());
            ADD_FAILURE() << "the writer wrote metadata the reader refuses";
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(out + ": cannot write: metadata: "
                                                       "georeference.geotransform"),
                      std::string::npos)
                << e.what();
        }
    }
    EXPECT_FALSE(std::filesystem::exists(out));
}

TEST(HostileRegions, AnHtj2kArchiveWithoutRidgeAllowHtj2kSaysSoAndHowToReadIt)
{
    // "corrupt payload" on every patch of an intact archive, and "a patch just encoded does
    // not decode" from a build, lost the reason: HTJ2K decoding is off by default.
    setenv("RIDGE_ALLOW_HTJ2K", "1", 1);
    const std::string path = test::buildEverestArchive(fixtures().dir, "jpeg2000,library=htj2k");
    unsetenv("RIDGE_ALLOW_HTJ2K");
    const archive::ArchiveReader reader(path);
    std::vector<uint16_t> codes(33 * 33);
    try {
        reader.decodePatch({0, 0, 0}, codes.data());
        ADD_FAILURE() << "HTJ2K decoded without RIDGE_ALLOW_HTJ2K";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("cannot decode: its decoder is disabled: HTJ2K "
                                             "payloads are decoded only with RIDGE_ALLOW_HTJ2K=1"),
                  std::string::npos)
            << e.what();
    }
    try {
        test::buildEverestArchive(fixtures().dir, "jpeg2000,library=htj2k,encoding=direct");
        ADD_FAILURE() << "an HTJ2K build ran without RIDGE_ALLOW_HTJ2K";
    } catch (const Error& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("RIDGE_ALLOW_HTJ2K=1"), std::string::npos) << m;
        EXPECT_EQ(m.find("internal error"), std::string::npos) << m;
    }
}
