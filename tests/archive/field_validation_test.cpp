// Every field of a .ridge archive is checked where the reader loads it, not only its CRC:
// real archives of the fixtures are patched field by field, every checksum is recomputed
// (test::ArchiveBytes::reseal), and the reader must refuse each with a message that starts
// with the archive path and names the field. And every archive ridge builds still opens.
#include "archive_bytes.h"
#include "archive_craft.h"
#include "fixture_archives.h"
#include "test_support.h"

#include "ridge/archive/archive_reader.h"
#include "ridge/core/error.h"
#include "ridge/core/parameter_check.h"
#include "ridge/io/raster_source.h"
#include "ridge/io/raster_writer.h"
#include "ridge/pipeline/build.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <zstd.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numeric>

using namespace ridge;
using test::ArchiveBytes;
namespace ho = test::header_offset;
namespace eo = test::entry_offset;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// The Everest fixture with patches of 33 (5 levels, 99 patches), built once per run.
struct Fixtures {
    test::ScratchDir dir;
    std::string lossless = test::buildEverestArchive(dir, "lossless");
    std::string raw = test::buildEverestArchive(dir, "raw");
    std::string progressive = test::buildEverestArchive(dir, "progressive");
    std::string crafted = dir.path("crafted.ridge");
};

const Fixtures& fixtures()
{
    static const Fixtures f;
    return f;
}

using Edit = std::function<void(ArchiveBytes&)>;

// Copies `archive`, applies `edit`, reseals every checksum and opens the result. Returns the
// reader's message, or "" when it opened.
std::string openCrafted(const std::string& archive, const Edit& edit)
{
    return test::openEdited(archive, fixtures().crafted, edit);
}

// The reader refused the crafted archive, saying where (the path first) and what (`phrase`),
// and not because of a checksum: reseal() left only the semantic checks to catch it.
::testing::AssertionResult refusedNaming(const std::string& message, const std::string& phrase)
{
    if (message.empty())
        return ::testing::AssertionFailure()
               << "the reader opened it (expected '" << phrase << "')";
    if (message.rfind(fixtures().crafted + ": ", 0) != 0)
        return ::testing::AssertionFailure() << "does not start with the path: " << message;
    if (message.find(phrase) == std::string::npos)
        return ::testing::AssertionFailure() << "expected '" << phrase << "' in: " << message;
    if (message.find("checksum") != std::string::npos)
        return ::testing::AssertionFailure()
               << "a checksum caught it, not a field check: " << message;
    return ::testing::AssertionSuccess() << message;
}

Edit setHeader(size_t offset, double value)
{
    return [=](ArchiveBytes& a) { a.set<double>(offset, value); };
}

Edit setHeaderU32(size_t offset, uint32_t value)
{
    return [=](ArchiveBytes& a) { a.set<uint32_t>(offset, value); };
}

// Index position of patch `p` in `archive`.
size_t entryOf(const std::string& archive, PatchId p)
{
    return static_cast<size_t>(archive::ArchiveReader(archive).geometry().patchIndex(p));
}

// "index entry 3, patch (level 1, x 0, y 1)".
std::string entryName(const std::string& archive, PatchId p)
{
    return "index entry " + std::to_string(entryOf(archive, p)) + ", " +
           archive::ArchiveReader::patchName(p);
}

Edit setEntry(size_t entry, size_t field, float value)
{
    return [=](ArchiveBytes& a) { a.setEntry<float>(entry, field, value); };
}

// An edit of the metadata document as JSON.
Edit editMetadata(const std::function<void(nlohmann::json&)>& change)
{
    return [=](ArchiveBytes& a) {
        nlohmann::json j = nlohmann::json::parse(a.metadata());
        change(j);
        a.setMetadata(j.dump(2));
    };
}

// Index entries in file order of their blobs.
std::vector<size_t> entriesByOffset(const ArchiveBytes& a)
{
    std::vector<size_t> order(a.entryCount());
    std::iota(order.begin(), order.end(), size_t{0});
    std::sort(order.begin(), order.end(), [&](size_t x, size_t y) {
        return a.entry<uint64_t>(x, eo::kOffset) < a.entry<uint64_t>(y, eo::kOffset);
    });
    return order;
}

} // namespace

// --- the harness itself ------------------------------------------------------------------

TEST(FieldValidation, ResealingKeepsAnArchiveValidAndIsWhatGetsCraftedBytesPastTheChecksums)
{
    const std::string& a = fixtures().lossless;
    EXPECT_EQ(openCrafted(a, [](ArchiveBytes&) {}), "");
    // Without reseal() the same edit is a checksum failure: the tests below really reach
    // the field checks.
    ArchiveBytes bytes(a);
    bytes.set<double>(ho::kSpacingX, kInf);
    bytes.save(fixtures().crafted);
    try {
        archive::ArchiveReader reader(fixtures().crafted);
        ADD_FAILURE() << "opened";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("header checksum"), std::string::npos) << e.what();
    }
}

// --- every archive ridge writes opens ----------------------------------------------------

TEST(FieldValidation, EveryArchiveRidgeBuildsFromTheFixturesOpens)
{
    test::ScratchDir dir;
    std::vector<std::string> archives;
    for (const std::string codec : {"lossless", "raw", "progressive", "progressive-paper"})
        archives.push_back(test::buildEverestArchive(dir, codec));
    archives.push_back(test::buildEverestArchive(dir, "lossless", 129)); // streamed
    archives.push_back(test::buildEverestArchive(dir, "lossless", 513)); // a single patch
    archives.push_back(test::buildEverestArchive(dir, "progressive", 65, 0.5));

    const auto build = [&](const std::string& source, const std::string& name, BuildOptions o) {
        o.progress = {};
        archives.push_back(dir.path(name));
        buildArchive(source, archives.back(), o);
    };
    BuildOptions neville;
    neville.patch_size = 33;
    neville.filter = PyramidFilter::Neville4;
    build(test::dataPath("everest_crop.tif"), "neville.ridge", neville);
    BuildOptions stored = neville;
    stored.filter = PyramidFilter::Decimate;
    stored.store_block_errors = true;
    build(test::dataPath("everest_crop.tif"), "stored.ridge", stored);
    BuildOptions voids;
    voids.patch_size = 65;
    build(test::dataPath("rainier_voids.tif"), "rainier.ridge", voids);
    voids.codec = "progressive";
    voids.max_error = 3.0;
    voids.store_block_errors = true;
    build(test::dataPath("rainier_voids.tif"), "rainier_progressive.ridge", voids);

    // A Float32 source that is not exact in 16 bits: quantization_error > 0 enters δ_l.
    const io::ElevationRaster everest = io::ingestRaster(test::dataPath("everest_crop.tif"));
    std::vector<float> metres(everest.grid.codes.size());
    for (size_t i = 0; i < metres.size(); ++i)
        metres[i] = float(everest.quantization.toMetres(everest.grid.codes[i]) + 0.137 * (i % 7));
    const std::string floats = dir.path("floats.tif");
    io::writeGeoTiff(floats, metres.data(), everest.grid.width, everest.grid.height, everest.geo);
    BuildOptions quantized;
    quantized.patch_size = 33;
    quantized.ingest.max_error = 0.3;
    build(floats, "floats.ridge", quantized);
    BuildOptions lossy;
    lossy.patch_size = 33;
    lossy.codec = "progressive";
    lossy.max_error = 1.5;
    lossy.filter = PyramidFilter::Neville4;
    build(floats, "floats_progressive.ridge", lossy);

    for (const std::string& path : archives) {
        SCOPED_TRACE(path);
        try {
            const archive::ArchiveReader reader(path);
            EXPECT_GT(reader.geometry().patchCount(), 0);
            if (path.find("floats") != std::string::npos) {
                EXPECT_GT(reader.header().quantization_error, 0.0);
            }
        } catch (const Error& e) {
            ADD_FAILURE() << e.what();
        }
    }
}

// --- header ------------------------------------------------------------------------------

TEST(FieldValidation, ReservedHeaderBytesMustBeZero)
{
    for (size_t byte = 88; byte < 96; ++byte)
        EXPECT_TRUE(refusedNaming(
            openCrafted(fixtures().lossless, [=](ArchiveBytes& a) { a.bytes()[byte] = 1; }),
            "header reserved bytes 88..95 are not zero (byte " + std::to_string(byte)));
    // Version 3 keeps its codec tables there (below); before, they are reserved.
    for (size_t byte = 140; byte < 156; ++byte)
        EXPECT_TRUE(refusedNaming(
            openCrafted(fixtures().lossless,
                        [=](ArchiveBytes& a) {
                            a.bytes()[8] = 2; // version 2
                            std::fill(a.bytes().begin() + 140, a.bytes().begin() + 156, 0);
                            a.bytes()[byte] = 0x80;
                        }),
            "header reserved bytes 140..155 are not zero (byte " + std::to_string(byte)));
}

TEST(FieldValidation, CodecTablesMustLieBetweenTheBlobsAndTheMetadataAndMatchTheirChecksum)
{
    // Offset and size (bytes 140..151) must put the region right before the metadata; the
    // checksum (152..155) must match, even for an empty region (crc 0).
    for (size_t byte = 140; byte < 152; ++byte)
        EXPECT_TRUE(refusedNaming(
            openCrafted(fixtures().lossless, [=](ArchiveBytes& a) { a.bytes()[byte] ^= 0x80; }),
            "header fields codec_tables_offset"))
            << byte;
    for (size_t byte = 152; byte < 156; ++byte)
        EXPECT_NE(
            openCrafted(fixtures().progressive, [=](ArchiveBytes& a) { a.bytes()[byte] ^= 1; })
                .find("codec tables checksum mismatch"),
            std::string::npos)
            << byte;
}

TEST(FieldValidation, HeightScaleAndOffsetMustBeFiniteAndKeepEveryCodeWithinTheHeightLimit)
{
    const std::string& a = fixtures().lossless;
    for (double v : {0.0, -1.0, kNaN, kInf, -kInf})
        EXPECT_TRUE(refusedNaming(openCrafted(a, setHeader(ho::kHeightScale, v)),
                                  "header field height_scale is " + formatNumber(v) +
                                      ": must be a finite number > 0"));
    for (double v : {kNaN, kInf, -kInf, 2e7, -1.5e7})
        EXPECT_TRUE(refusedNaming(openCrafted(a, setHeader(ho::kHeightOffset, v)),
                                  "header field height_offset is " + formatNumber(v) +
                                      ": must be a number in [-1e+07, 1e+07]"));
    // Every code's height counts: offset 0 is fine, but 65535 codes of 200 m reach 1.3e7 m.
    EXPECT_TRUE(
        refusedNaming(openCrafted(a,
                                  [](ArchiveBytes& b) {
                                      b.set<double>(ho::kHeightOffset, 0.0);
                                      b.set<double>(ho::kHeightScale, 200.0);
                                  }),
                      "height_offset + 65535 * height_scale (the height of code 65535) are " +
                          formatNumber(65535 * 200.0) + ": must be a number in [-1e+07, 1e+07]"));
    EXPECT_TRUE(refusedNaming(openCrafted(a, setHeader(ho::kHeightScale, 1e300)),
                              "height_offset + 65535 * height_scale"));
}

TEST(FieldValidation, SpacingsMustBePositiveFiniteAndAtMostTheSpacingLimit)
{
    const std::string& a = fixtures().lossless;
    for (const auto& [offset, name] :
         {std::pair{ho::kSpacingX, "spacing_x"}, std::pair{ho::kSpacingY, "spacing_y"}})
        for (double v : {0.0, -82.0, kNaN, kInf, -kInf, 1.0000001e7})
            EXPECT_TRUE(refusedNaming(openCrafted(a, setHeader(offset, v)),
                                      std::string("header field ") + name + " is " +
                                          formatNumber(v) + ": must be a number in (0, 1e+07]"));
    EXPECT_EQ(openCrafted(a, setHeader(ho::kSpacingX, 1e7)), "") << "the limit itself is allowed";
}

TEST(FieldValidation, QuantizationErrorMustBeFiniteNonNegativeAndWithinTheCodeRange)
{
    for (double v : {-0.5, kNaN, kInf, 65535.5})
        EXPECT_TRUE(
            refusedNaming(openCrafted(fixtures().lossless, setHeader(ho::kQuantizationError, v)),
                          "header field quantization_error is " + formatNumber(v) +
                              ": must be a number in [0, 65535]"));
}

TEST(FieldValidation, CodecParametersAreCheckedByTheCodecAndNamed)
{
    const Fixtures& f = fixtures();
    EXPECT_TRUE(refusedNaming(openCrafted(f.lossless, setHeader(ho::kCodecParam0, 0.5)),
                              "header field codec_param[0] is 0.5: the lossless codec takes no "
                              "parameters (must be 0)"));
    EXPECT_TRUE(refusedNaming(openCrafted(f.lossless, setHeader(ho::kCodecParam1, kNaN)),
                              "header field codec_param[1] is nan: the lossless codec"));
    EXPECT_TRUE(
        refusedNaming(openCrafted(f.raw, setHeader(ho::kCodecParam0, 1.0)),
                      "header field codec_param[0] is 1: the raw codec takes no parameters"));
    for (double v : {-1.0, 32767.5, kNaN, kInf})
        EXPECT_TRUE(refusedNaming(openCrafted(f.progressive, setHeader(ho::kCodecParam0, v)),
                                  "header field codec_param[0] is " + formatNumber(v) +
                                      ": the progressive codec's finest-level bound"));
    for (double v : {1.0, 3.0, 8.0, 2.5, kNaN})
        EXPECT_TRUE(refusedNaming(openCrafted(f.progressive, setHeader(ho::kCodecParam1, v)),
                                  "header field codec_param[1] is " + formatNumber(v) +
                                      ": the progressive codec's variant must be 0, 2, 4 or 6"));
    EXPECT_TRUE(refusedNaming(openCrafted(f.lossless, setHeaderU32(ho::kCodecId, 7)),
                              "header field codec_id is 7: must be 0 (raw), 1 (lossless), 2"));
}

TEST(FieldValidation, GeometryLayoutAndFilterFieldsAreNamed)
{
    const std::string& a = fixtures().lossless;
    EXPECT_TRUE(refusedNaming(openCrafted(a, setHeaderU32(ho::kWidth, 0xffffffffu)),
                              "header field width is 4294967295: must be an integer in [2, "
                              "2147483647]"));
    EXPECT_TRUE(
        refusedNaming(openCrafted(a, setHeaderU32(ho::kHeight, 1)), "header field height is 1"));
    EXPECT_TRUE(refusedNaming(openCrafted(a, setHeaderU32(ho::kPatchSize, 100)),
                              "header field patch_size is 100: must be 2^k + 1"));
    EXPECT_TRUE(refusedNaming(openCrafted(a, setHeaderU32(ho::kLevelCount, 9)),
                              "header field level_count is 9: must be 5"));
    EXPECT_TRUE(refusedNaming(openCrafted(a, setHeaderU32(ho::kBlockCells, 6)),
                              "header field block_cells is 6"));
    EXPECT_TRUE(
        refusedNaming(openCrafted(a, setHeaderU32(ho::kBlockLevels, 1)),
                      "header field block_levels is 1: must be min(4, log2 block_cells) = 3"));
    EXPECT_TRUE(refusedNaming(openCrafted(a, setHeaderU32(ho::kFilterId, 2)),
                              "header field filter_id is 2"));
    EXPECT_TRUE(refusedNaming(openCrafted(a, setHeaderU32(12, 161)),
                              "header field header_size is 161: must be 160"));
}

TEST(FieldValidation, MetadataMustBeAnObjectRightBeforeTheIndex)
{
    const std::string& a = fixtures().lossless;
    EXPECT_TRUE(refusedNaming(openCrafted(a, setHeaderU32(ho::kMetadataSize, 1)),
                              "header field metadata_size is 1: must be >= 2"));
    // One byte between the metadata and the index would belong to no checksummed region.
    EXPECT_TRUE(refusedNaming(
        openCrafted(
            a, [](ArchiveBytes& b) { b.set<uint32_t>(ho::kMetadataSize, b.metadataSize() - 1); }),
        "metadata_offset + metadata_size"));
}

// --- index -------------------------------------------------------------------------------

TEST(FieldValidation, IndexHeightsAndErrorsMustBeFinite)
{
    const std::string& a = fixtures().lossless;
    const PatchId p{1, 1, 0};
    const size_t e = entryOf(a, p);
    for (const auto& [field, name] :
         {std::pair{eo::kMinHeight, "min_height"}, std::pair{eo::kMaxHeight, "max_height"},
          std::pair{eo::kErrAppr, "err_appr"}, std::pair{eo::kErr, "err"}})
        for (float v : {float(kNaN), float(kInf), -float(kInf)})
            EXPECT_TRUE(refusedNaming(openCrafted(a, setEntry(e, field, v)),
                                      entryName(a, p) + ": " + name + " is " + formatNumber(v) +
                                          ": must be a finite number"));
}

TEST(FieldValidation, IndexMinMaxMustBeOrderedAndWithinTheCodeRange)
{
    const std::string& a = fixtures().lossless;
    const PatchId p{2, 1, 1};
    const size_t e = entryOf(a, p);
    const archive::PatchRecord r = archive::ArchiveReader(a).record(p);
    EXPECT_TRUE(refusedNaming(openCrafted(a, setEntry(e, eo::kMinHeight, r.max_height + 1)),
                              entryName(a, p) + ": min_height " + formatNumber(r.max_height + 1) +
                                  " > max_height " + formatNumber(r.max_height)));
    // Everest is Int16: codes 0..65535 are -32768..32767 m; lossless, so δ_l = 0.
    EXPECT_TRUE(
        refusedNaming(openCrafted(fixtures().lossless, setEntry(0, eo::kMinHeight, -1e6f)),
                      "index entry 0, patch (level 0, x 0, y 0): min_height is -1e+06: must "
                      "be a number in [-32768, 32767]"));
    EXPECT_TRUE(
        refusedNaming(openCrafted(fixtures().lossless, setEntry(0, eo::kMaxHeight, 32768.f)),
                      "max_height is 32768: must be a number in [-32768, 32767]"));
}

TEST(FieldValidation, IndexErrApprIsZeroAtTheFinestLevelAndAtMostTheCodeRangePerLevelBelow)
{
    const std::string& a = fixtures().lossless;
    EXPECT_TRUE(refusedNaming(openCrafted(a,
                                          [](ArchiveBytes& b) {
                                              b.setEntry<float>(0, eo::kErrAppr, -1.f);
                                              b.setEntry<float>(0, eo::kErr, 0.f);
                                          }),
                              "index entry 0, patch (level 0, x 0, y 0): err_appr is -1: must be a "
                              "number in [0, "));
    EXPECT_TRUE(refusedNaming(openCrafted(a,
                                          [](ArchiveBytes& b) {
                                              b.setEntry<float>(0, eo::kErrAppr, 1e30f);
                                              b.setEntry<float>(0, eo::kErr, 1e30f);
                                          }),
                              "err_appr is 1e+30: must be a number in [0, 262140."));
    const PatchId finest{4, 3, 2};
    const size_t e = entryOf(a, finest);
    EXPECT_TRUE(
        refusedNaming(openCrafted(a,
                                  [=](ArchiveBytes& b) {
                                      b.setEntry<float>(e, eo::kErrAppr, 0.5f);
                                      b.setEntry<float>(e, eo::kErr, 0.5f);
                                  }),
                      entryName(a, finest) + ": err_appr is 0.5: must be 0 at the finest level"));
}

TEST(FieldValidation, IndexErrIsErrApprPlusTheLevelBoundRoundedUp)
{
    const std::string& a = fixtures().lossless;
    const PatchId p{1, 0, 0};
    const size_t e = entryOf(a, p);
    const archive::PatchRecord r = archive::ArchiveReader(a).record(p);
    ASSERT_GT(r.err_appr, 2.f);
    EXPECT_TRUE(refusedNaming(openCrafted(a, setEntry(e, eo::kErr, r.err_appr - 1)),
                              entryName(a, p) + ": err is " + formatNumber(r.err_appr - 1) +
                                  ": must be a number in [" + formatNumber(r.err_appr)));
    EXPECT_TRUE(refusedNaming(openCrafted(a, setEntry(e, eo::kErr, r.err_appr + 1)),
                              entryName(a, p) + ": err is " + formatNumber(r.err_appr + 1)));
    // A lossy codec's finest patch: Err_Appr 0, so Err must be δ_l (rounded up), not less.
    const std::string& lossy = fixtures().progressive;
    const archive::ArchiveReader reader(lossy);
    const int finest = reader.geometry().finestLevel();
    ASSERT_GT(reader.levelErrorBound(finest), 0.0);
    const PatchId q{finest, 0, 0};
    EXPECT_TRUE(refusedNaming(openCrafted(lossy, setEntry(entryOf(lossy, q), eo::kErr, 0.f)),
                              entryName(lossy, q) + ": err is 0: must be a number in [" +
                                  formatNumber(reader.levelErrorBound(finest))));
}

TEST(FieldValidation, ParentsBoundsCoverTheirChildrenAndTheirErrApprIsNotSmaller)
{
    const std::string& a = fixtures().lossless;
    const archive::ArchiveReader reader(a);
    const PatchId parent{1, 1, 0}, child{2, 2, 1};
    ASSERT_EQ(child.parent(), parent);
    const archive::PatchRecord P = reader.record(parent), C = reader.record(child);
    const size_t c = entryOf(a, child);
    const std::string prefix = entryName(a, parent) + ": ";
    const std::string of_child = " of its child " + archive::ArchiveReader::patchName(child);
    EXPECT_TRUE(refusedNaming(openCrafted(a, setEntry(c, eo::kMinHeight, P.min_height - 1)),
                              prefix + "min_height " + formatNumber(P.min_height) +
                                  " > min_height " + formatNumber(P.min_height - 1) + of_child));
    EXPECT_TRUE(refusedNaming(openCrafted(a, setEntry(c, eo::kMaxHeight, P.max_height + 1)),
                              prefix + "max_height " + formatNumber(P.max_height) +
                                  " < max_height " + formatNumber(P.max_height + 1) + of_child));
    // The child alone stays consistent (Err = Err_Appr: lossless, exact source).
    const float bigger = P.err_appr + 1;
    ASSERT_GT(bigger, C.err_appr);
    EXPECT_TRUE(refusedNaming(openCrafted(a,
                                          [=](ArchiveBytes& b) {
                                              b.setEntry<float>(c, eo::kErrAppr, bigger);
                                              b.setEntry<float>(c, eo::kErr, bigger);
                                          }),
                              prefix + "err_appr " + formatNumber(P.err_appr) + " < err_appr " +
                                  formatNumber(bigger) + of_child));
}

TEST(FieldValidation, BlobsLieInThePatchAreaSplitSensiblyAndTileItWithoutOverlap)
{
    const std::string& a = fixtures().lossless;
    const PatchId p{2, 0, 1};
    const size_t e = entryOf(a, p);
    const std::string name = entryName(a, p);
    EXPECT_TRUE(refusedNaming(
        openCrafted(a, [=](ArchiveBytes& b) { b.setEntry<uint64_t>(e, eo::kOffset, 100); }),
        name + ": blob at offset 100, size "));
    EXPECT_TRUE(refusedNaming(
        openCrafted(a, [=](ArchiveBytes& b) { b.setEntry<uint32_t>(e, eo::kBlockErrorsSize, 5); }),
        name + ": block_errors_size is 5: must be 0 (not stored) or >= 14"));
    EXPECT_TRUE(refusedNaming(openCrafted(a,
                                          [=](ArchiveBytes& b) {
                                              b.setEntry<uint32_t>(e, eo::kBlockErrorsSize,
                                                                   b.entry<uint32_t>(e, eo::kSize));
                                          }),
                              name + ": block_errors_size " +
                                  std::to_string(ArchiveBytes(a).entry<uint32_t>(e, eo::kSize)) +
                                  " leaves no payload"));
    // The last blob in the file claims the first blob's bytes.
    EXPECT_TRUE(refusedNaming(
        openCrafted(a,
                    [](ArchiveBytes& b) {
                        const std::vector<size_t> order = entriesByOffset(b);
                        b.setEntry<uint64_t>(order.back(), eo::kOffset,
                                             b.entry<uint64_t>(order.front(), eo::kOffset));
                        b.setEntry<uint32_t>(order.back(), eo::kSize,
                                             b.entry<uint32_t>(order.front(), eo::kSize));
                    }),
        "overlaps the blob of"));
    // A blob one byte shorter leaves a byte that belongs to no checksummed region.
    EXPECT_TRUE(refusedNaming(openCrafted(a,
                                          [](ArchiveBytes& b) {
                                              const size_t first = entriesByOffset(b).front();
                                              b.setEntry<uint32_t>(
                                                  first, eo::kSize,
                                                  b.entry<uint32_t>(first, eo::kSize) - 1);
                                          }),
                              "belong to no patch"));
    EXPECT_TRUE(
        refusedNaming(openCrafted(a, [=](ArchiveBytes& b) { b.setEntry<uint32_t>(e, eo::kX, 7); }),
                      "index entry " + std::to_string(e) + " is out of order"));
}

namespace {

// The header and metadata of a `side` × `side` grid in `levels` levels (blobs and index as
// they are).
void setSquareGeometry(ArchiveBytes& b, uint32_t side, int levels)
{
    b.set<uint32_t>(ho::kWidth, side);
    b.set<uint32_t>(ho::kHeight, side);
    b.set<uint32_t>(ho::kLevelCount, uint32_t(levels));
    editMetadata([=](nlohmann::json& j) {
        j["source"]["width"] = side;
        j["source"]["height"] = side;
    })(b);
}

} // namespace

TEST(FieldValidation, AHugeGeometryIsComparedWithTheFileBeforeItsIndexSizeIsComputed)
{
    // 2^31 - 1 samples a side in patches of 33: 27 levels, ~6e15 patches, a 3e17-byte index.
    constexpr uint32_t kHuge = 2147483647u;
    const PyramidGeometry huge(static_cast<int>(kHuge), static_cast<int>(kHuge), 33);
    EXPECT_TRUE(refusedNaming(
        openCrafted(fixtures().lossless,
                    [&](ArchiveBytes& b) { setSquareGeometry(b, kHuge, huge.levelCount()); }),
        "index lies outside the file"));
}

// A packed index (format 5) is a zstd frame, which may expand a thousandfold: a geometry of
// more patches than the blobs could hold is refused before the frame is decompressed, even
// when the frame states exactly the content those patches need (a "zip bomb" of zeros).
TEST(FieldValidation, APackedIndexIsNotUnpackedForMorePatchesThanTheBlobsCanHold)
{
    const archive::ArchiveReader original(fixtures().lossless);
    ASSERT_GE(original.header().version, 5u);
    const uint32_t side = 16385; // ~65 000 patches of 33: far more than the fixture's blobs hold
    const PyramidGeometry big(static_cast<int>(side), static_cast<int>(side),
                              original.geometry().patchSize());
    const size_t content = size_t(big.patchCount()) * 48;
    const std::vector<uint8_t> zeros(content, 0);
    std::vector<uint8_t> frame(ZSTD_compressBound(content));
    frame.resize(ZSTD_compress(frame.data(), frame.size(), zeros.data(), zeros.size(), 19));
    ASSERT_LT(frame.size(), content / 100) << "a frame that expands a hundredfold";
    EXPECT_TRUE(refusedNaming(openCrafted(fixtures().lossless,
                                          [&](ArchiveBytes& b) {
                                              setSquareGeometry(b, side, big.levelCount());
                                              b.setOpaqueIndex(frame);
                                          }),
                              "patches need at least 3 blob bytes each"));
}

// --- metadata ----------------------------------------------------------------------------

TEST(FieldValidation, MetadataMustBeAJsonObject)
{
    const std::string& a = fixtures().lossless;
    const auto text = [](std::string json) {
        return [=](ArchiveBytes& b) { b.setMetadata(json); };
    };
    EXPECT_TRUE(
        refusedNaming(openCrafted(a, text("{not json")), "metadata: not JSON: parse error"));
    EXPECT_TRUE(refusedNaming(openCrafted(a, text("{\"a\": \"\xff\"}")), "metadata: not JSON"));
    EXPECT_TRUE(refusedNaming(openCrafted(a, text("{\"a\": 1e999}")),
                              "metadata: not JSON: number overflow parsing '1e999'"));
    EXPECT_TRUE(refusedNaming(openCrafted(a, text("[1, 2]")),
                              "metadata: not a JSON object (it is an array)"));
    EXPECT_TRUE(refusedNaming(openCrafted(a, text("\"x\"")),
                              "metadata: not a JSON object (it is a string)"));
    EXPECT_TRUE(refusedNaming(openCrafted(a, text("{}")), "metadata: source is missing"));
}

TEST(FieldValidation, EveryDocumentedMetadataKeyIsRequiredAndNamedWhenMissing)
{
    const std::vector<std::pair<std::string, std::string>> keys = {
        {"source", "path"},
        {"source", "data_type"},
        {"source", "width"},
        {"source", "height"},
        {"source", "valid_samples"},
        {"source", "voids_filled"},
        {"source", "void_fill"},
        {"source", "min_metres"},
        {"source", "max_metres"},
        {"source", "exact"},
        {"georeference", "crs_wkt"},
        {"georeference", "geographic"},
        {"georeference", "vertical_units"},
        {"georeference", "spacing_from_user"},
        {"build", "patch_size"},
        {"build", "block_cells"},
        {"build", "codec"},
        {"build", "filter"},
        {"build", "z_scale"},
        {"build", "z_offset"},
        {"", "source"},
        {"", "georeference"},
        {"", "build"},
        {"", "generator"}};
    for (const auto& [section, key] : keys) {
        const std::string name = section.empty() ? key : section + "." + key;
        EXPECT_TRUE(refusedNaming(
            openCrafted(fixtures().lossless,
                        editMetadata([&, &section = section, &key = key](nlohmann::json& j) {
                            (section.empty() ? j : j[section]).erase(key);
                        })),
            "metadata: " + name + " is missing"));
    }
}

TEST(FieldValidation, MetadataValuesMustHaveTheirDocumentedTypes)
{
    struct Case {
        std::string section, key;
        nlohmann::json value;
        std::string phrase;
    };
    const std::vector<Case> cases = {
        {"source", "path", 7, "metadata: source.path is 7: must be a string"},
        {"source", "width", 301.5, "metadata: source.width is 301.5: must be an integer"},
        {"source", "width", "301", "metadata: source.width is \"301\": must be an integer"},
        {"source", "valid_samples", nullptr,
         "metadata: source.valid_samples is null: must be an integer"},
        {"source", "min_metres", "low", "metadata: source.min_metres is \"low\": must be a number"},
        {"source", "exact", 1, "metadata: source.exact is 1: must be true or false"},
        {"georeference", "geographic", "yes",
         "metadata: georeference.geographic is \"yes\": must be true or false"},
        {"georeference", "crs_wkt", false,
         "metadata: georeference.crs_wkt is false: must be a string"},
        {"georeference",
         "geotransform",
         {1, 2, 3},
         "metadata: georeference.geotransform is [1,2,3]: must be an array of 6 numbers"},
        {"georeference",
         "geotransform",
         {1, 2, 3, 4, "5", 6},
         "metadata: georeference.geotransform[4] is \"5\": must be a number"},
        {"build", "z_scale", "1", "metadata: build.z_scale is \"1\": must be a number"},
        {"build", "codec", 1, "metadata: build.codec is 1: must be a string"},
        {"build", "max_error", "2", "metadata: build.max_error is \"2\": must be a number"},
        {"build", "codec_variant", 6, "metadata: build.codec_variant is 6: must be a string"},
        {"", "source", nlohmann::json::array(), "metadata: source is []: must be an object"},
        {"", "generator", 1, "metadata: generator is 1: must be a string"},
    };
    for (const Case& c : cases)
        EXPECT_TRUE(
            refusedNaming(openCrafted(fixtures().lossless, editMetadata([&](nlohmann::json& j) {
                                          (c.section.empty() ? j : j[c.section])[c.key] = c.value;
                                      })),
                          c.phrase));
}

TEST(FieldValidation, MetadataThatRepeatsTheHeaderMustAgreeWithIt)
{
    const auto set = [](const char* section, const char* key, nlohmann::json value) {
        return editMetadata([=](nlohmann::json& j) { j[section][key] = value; });
    };
    const Fixtures& f = fixtures();
    EXPECT_TRUE(refusedNaming(openCrafted(f.lossless, set("source", "width", 300)),
                              "metadata: source.width is 300 but the header's width is 301"));
    EXPECT_TRUE(refusedNaming(openCrafted(f.lossless, set("source", "height", 204)),
                              "metadata: source.height is 204 but the header's height is 203"));
    EXPECT_TRUE(
        refusedNaming(openCrafted(f.lossless, set("build", "patch_size", 65)),
                      "metadata: build.patch_size is 65 but the header's patch_size is 33"));
    EXPECT_TRUE(
        refusedNaming(openCrafted(f.lossless, set("build", "block_cells", 4)),
                      "metadata: build.block_cells is 4 but the header's block_cells is 8"));
    EXPECT_TRUE(refusedNaming(
        openCrafted(f.lossless, set("build", "codec", "raw")),
        "metadata: build.codec is \"raw\" (codec id 0) but the header's codec_id is 1"));
    EXPECT_TRUE(refusedNaming(
        openCrafted(f.progressive, set("build", "codec", "lossless")),
        "metadata: build.codec is \"lossless\" (codec id 1) but the header's codec_id is 2"));
    EXPECT_EQ(openCrafted(f.progressive, set("build", "codec", "progressive-paper")), "")
        << "both progressive names are codec 2";
    EXPECT_TRUE(refusedNaming(openCrafted(f.lossless, set("build", "codec", "jpeg9000")),
                              "metadata: build.codec is \"jpeg9000\": not a codec ("));
    EXPECT_TRUE(refusedNaming(
        openCrafted(f.lossless, set("build", "filter", "neville")),
        "metadata: build.filter is \"neville\" but the header's filter_id 0 is \"decimate\""));
    // Everest is exact (Int16): a quantization error contradicts source.exact.
    EXPECT_TRUE(refusedNaming(
        openCrafted(f.lossless, setHeader(ho::kQuantizationError, 0.25)),
        "metadata: source.exact is true but the header's quantization_error is 0.25"));
}

TEST(FieldValidation, MetadataNumbersAndCountsMustBeInRange)
{
    const auto set = [](const char* section, const char* key, nlohmann::json value) {
        return editMetadata([=](nlohmann::json& j) { j[section][key] = value; });
    };
    const std::string& a = fixtures().lossless;
    EXPECT_TRUE(refusedNaming(openCrafted(a, set("source", "valid_samples", -1)),
                              "metadata: source.valid_samples is -1: must be an integer in [0, "));
    EXPECT_TRUE(
        refusedNaming(openCrafted(a, set("source", "voids_filled", 301 * 203 + 1)),
                      "metadata: source.voids_filled is 61104: must be an integer in [0, 61103]"));
    EXPECT_TRUE(refusedNaming(openCrafted(a, set("source", "min_metres", 9000.5)),
                              "metadata: source.min_metres 9000.5 > source.max_metres"));
    EXPECT_TRUE(
        refusedNaming(openCrafted(a, set("build", "z_scale", 0)),
                      "metadata: build.z_scale is 0: must be a finite number other than 0"));
    EXPECT_TRUE(refusedNaming(openCrafted(a, set("build", "max_error", -1)),
                              "metadata: build.max_error is -1: must be a finite number >= 0"));
    EXPECT_TRUE(
        refusedNaming(openCrafted(a, set("build", "codec_max_error", -0.5)),
                      "metadata: build.codec_max_error is -0.5: must be a finite number >= 0"));
}

TEST(FieldValidation, UnknownMetadataKeysAreIgnoredAndOptionalOnesMayBeMissing)
{
    const std::string& a = fixtures().lossless;
    EXPECT_EQ(openCrafted(a, editMetadata([](nlohmann::json& j) {
                              j["future"] = {{"anything", {1, 2, 3}}};
                              j["source"]["future_count"] = "many";
                              j["build"]["future_flag"] = true;
                          })),
              "");
    EXPECT_EQ(openCrafted(a, editMetadata([](nlohmann::json& j) {
                              j["georeference"].erase("geotransform");
                              j["build"].erase("block_errors");
                              j["build"].erase("max_error");
                              j["build"].erase("codec_max_error");
                              j["build"].erase("codec_variant");
                          })),
              "");
}

// --- the two crashes of the review -------------------------------------------------------

TEST(FieldValidation, TheArchivesThatCrashedTheRendererAreRefusedAtOpen)
{
    const std::string& a = fixtures().lossless;
    EXPECT_TRUE(refusedNaming(openCrafted(a,
                                          [](ArchiveBytes& b) {
                                              b.setEntry<float>(0, eo::kMinHeight, float(kNaN));
                                              b.setEntry<float>(0, eo::kMaxHeight, float(kNaN));
                                          }),
                              "index entry 0, patch (level 0, x 0, y 0): min_height is nan"));
    EXPECT_TRUE(refusedNaming(openCrafted(a, setHeader(ho::kSpacingX, kInf)),
                              "header field spacing_x is inf: must be a number in (0, 1e+07]"));
}
