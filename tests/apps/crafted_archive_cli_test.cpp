// Archives with valid checksums but fields that mean nothing (the robustness review's crafted
// archives), as a user meets them: `ridge verify`, `info`, `extract` and `render` each refuse
// them with exit code 1 (not 0, not a signal), a message that names the field, and no output
// left behind. Among them the two that crashed the default `ridge render`: a NaN root
// min/max and an infinite spacing_x; and the metadata nested 100,000 deep that crashed every
// command, and what some commands accepted and others refused (issue 23).
#include "archive_bytes.h"
#include "archive_craft.h"
#include "test_support.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <functional>
#include <limits>
#include <numeric>

using namespace ridge;
using test::ArchiveBytes;
namespace fs = std::filesystem;
namespace ho = test::header_offset;
namespace eo = test::entry_offset;

namespace {

constexpr float kNaNf = std::numeric_limits<float>::quiet_NaN();

struct Craft {
    std::string name;                        // file name of the crafted archive
    std::function<void(ArchiveBytes&)> edit; // applied before every checksum is recomputed
    std::string phrase;                      // what the message must say
};

std::vector<Craft> crafts()
{
    return {
        {"root_minmax_nan.ridge",
         [](ArchiveBytes& a) {
             a.setEntry<float>(0, eo::kMinHeight, kNaNf);
             a.setEntry<float>(0, eo::kMaxHeight, kNaNf);
         },
         "index entry 0, patch (level 0, x 0, y 0): min_height is nan"},
        {"spacing_inf.ridge",
         [](ArchiveBytes& a) {
             a.set<double>(ho::kSpacingX, std::numeric_limits<double>::infinity());
         },
         "header field spacing_x is inf: must be a number in (0, 1e+07]"},
        {"scale_zero.ridge", [](ArchiveBytes& a) { a.set<double>(ho::kHeightScale, 0.0); },
         "header field height_scale is 0"},
        {"reserved.ridge", [](ArchiveBytes& a) { a.bytes()[90] = 1; },
         "header reserved bytes 88..95 are not zero"},
        {"tables.ridge", [](ArchiveBytes& a) { a.bytes()[150] = 1; },
         "header fields codec_tables_offset"},
        {"codec_param.ridge", [](ArchiveBytes& a) { a.set<double>(ho::kCodecParam0, 2.0); },
         "header field codec_param[0] is 2: the lossless codec takes no parameters"},
        {"min_above_max.ridge",
         [](ArchiveBytes& a) {
             a.setEntry<float>(1, eo::kMinHeight, a.entry<float>(1, eo::kMaxHeight) + 10);
         },
         "index entry 1, patch (level 1, x 0, y 0): min_height"},
        {"err_inf.ridge",
         [](ArchiveBytes& a) {
             a.setEntry<float>(2, eo::kErr, std::numeric_limits<float>::infinity());
         },
         "index entry 2, patch (level 1, x 1, y 0): err is inf"},
        {"overlap.ridge",
         [](ArchiveBytes& a) {
             std::vector<size_t> order(a.entryCount());
             std::iota(order.begin(), order.end(), size_t{0});
             std::sort(order.begin(), order.end(), [&](size_t x, size_t y) {
                 return a.entry<uint64_t>(x, eo::kOffset) < a.entry<uint64_t>(y, eo::kOffset);
             });
             a.setEntry<uint64_t>(order.back(), eo::kOffset,
                                  a.entry<uint64_t>(order.front(), eo::kOffset));
             a.setEntry<uint32_t>(order.back(), eo::kSize,
                                  a.entry<uint32_t>(order.front(), eo::kSize));
         },
         "overlaps the blob of"},
        {"metadata_text.ridge", [](ArchiveBytes& a) { a.setMetadata("ridge archive, v1"); },
         "metadata: not JSON"},
        {"metadata_patch.ridge",
         [](ArchiveBytes& a) {
             nlohmann::json j = nlohmann::json::parse(a.metadata());
             j["build"]["patch_size"] = 65;
             a.setMetadata(j.dump());
         },
         "metadata: build.patch_size is 65 but the header's patch_size is 33"},
        // The optional keys of issue 22: checked when present.
        {"metadata_band.ridge",
         [](ArchiveBytes& a) {
             nlohmann::json j = nlohmann::json::parse(a.metadata());
             j["source"]["band"] = 0;
             a.setMetadata(j.dump());
         },
         "metadata: source.band is 0: must be an integer in [1, 65536]"},
        {"metadata_datum_name.ridge",
         [](ArchiveBytes& a) {
             nlohmann::json j = nlohmann::json::parse(a.metadata());
             j["georeference"]["vertical_datum"] = {{"name", ""}, {"epsg", 5773}};
             a.setMetadata(j.dump());
         },
         "metadata: georeference.vertical_datum.name is "},
        {"metadata_datum_epsg.ridge",
         [](ArchiveBytes& a) {
             nlohmann::json j = nlohmann::json::parse(a.metadata());
             j["georeference"]["vertical_datum"] = {{"name", "EGM96 height"}, {"epsg", "5773"}};
             a.setMetadata(j.dump());
         },
         "metadata: georeference.vertical_datum.epsg is "},
        {"metadata_datum_kind.ridge",
         [](ArchiveBytes& a) {
             nlohmann::json j = nlohmann::json::parse(a.metadata());
             j["georeference"]["vertical_datum"] = "EGM96 height";
             a.setMetadata(j.dump());
         },
         "metadata: georeference.vertical_datum is "},
        // Issue 23: each of these crashed (SIGSEGV, the first) or passed some commands.
        {"metadata_deep.ridge",
         [](ArchiveBytes& a) {
             nlohmann::json j = nlohmann::json::parse(a.metadata());
             j["generator"] = "@";
             std::string text = j.dump();
             text.replace(text.find("\"@\""), 3,
                          std::string(100000, '[') + std::string(100000, ']'));
             a.setMetadata(text);
         },
         "metadata: values nested more than 32 deep"},
        {"metadata_nul.ridge",
         [](ArchiveBytes& a) { a.setMetadata(a.metadata() + std::string("\0{\"x\":1}", 8)); },
         "metadata: not JSON: a NUL byte at offset"},
        {"geotransform_zero.ridge",
         [](ArchiveBytes& a) {
             nlohmann::json j = nlohmann::json::parse(a.metadata());
             j["georeference"]["geotransform"] = {0, 0, 0, 0, 0, 0};
             a.setMetadata(j.dump());
         },
         "metadata: georeference.geotransform is [0,0,0,0,0,0]: its pixels have zero area"},
        {"tables_on_lossless.ridge",
         [](ArchiveBytes& a) {
             test::setCodecTables(a, {'T', 1, 5, 0});
         },
         "codec tables region of 4 bytes: the lossless codec has no codec tables"},
    };
}

// The command failed the way a user can act on: exit 1, the archive and the field named, no
// crash.
void expectRefused(const test::CommandResult& r, const std::string& archive,
                   const std::string& phrase, const std::string& command)
{
    EXPECT_EQ(r.exit_code, 1) << command << ": " << r.output;
    EXPECT_NE(r.output.find(archive + ": "), std::string::npos) << command << ": " << r.output;
    EXPECT_NE(r.output.find(phrase), std::string::npos)
        << command << ": expected '" << phrase << "' in: " << r.output;
}

// Nothing but the archives in `dir`: no output file, no temporary.
void expectNoOutput(const test::ScratchDir& dir)
{
    for (const auto& entry : fs::directory_iterator(dir.dir()))
        EXPECT_EQ(entry.path().extension(), ".ridge") << "left behind: " << entry.path();
}

} // namespace

TEST(CraftedArchiveCli, TheCraftsAreValidArchivesApartFromTheFieldTheyBreak)
{
    // The untouched archive, resealed, passes every command: the refusals below are the
    // field checks, not the resealing.
    test::ScratchDir dir;
    const std::string base = test::buildEverestWithCli(dir, "base.ridge", "--patch 33");
    ArchiveBytes bytes(base);
    bytes.reseal();
    const std::string same = dir.path("same.ridge");
    bytes.save(same);
    EXPECT_EQ(test::runRidge("verify '" + same + "' -q").exit_code, 0);
    EXPECT_EQ(test::runRidge("info '" + same + "'").exit_code, 0);
}

TEST(CraftedArchiveCli, VerifyInfoExtractAndRenderRefuseEachWithExitOneNamingTheField)
{
    test::ScratchDir dir;
    const std::string base = test::buildEverestWithCli(dir, "base.ridge", "--patch 33");
    for (const Craft& c : crafts()) {
        SCOPED_TRACE(c.name);
        const std::string path = dir.path(c.name);
        ArchiveBytes bytes(base);
        c.edit(bytes);
        bytes.reseal();
        bytes.save(path);
        const std::string q = "'" + path + "'";

        const test::CommandResult verify = test::runRidge("verify " + q + " -q");
        expectRefused(verify, path, c.phrase, "verify");
        EXPECT_NE(verify.output.find("verify FAILED"), std::string::npos) << verify.output;
        expectRefused(test::runRidge("info " + q), path, c.phrase, "info");
        expectRefused(test::runRidge("info " + q + " --json"), path, c.phrase, "info --json");
        expectRefused(test::runRidge("extract " + q + " -o '" + dir.path("out.tif") + "' -q"), path,
                      c.phrase, "extract");
        // The default camera: what crashed on a NaN root box and an infinite spacing.
        expectRefused(
            test::runRidge("render " + q + " -o '" + dir.path("out.png") + "' --size 64x48 -q"),
            path, c.phrase, "render");
        expectRefused(test::runRidge("query " + q + " 10 10 --pixel"), path, c.phrase, "query");
        expectRefused(test::runRidge("verify " + q + " --json"), path, c.phrase, "verify --json");
        expectNoOutput(dir);
    }
}

TEST(CraftedArchiveCli, AnHtj2kArchiveWithoutRidgeAllowHtj2kIsOneProblemNamingTheVariable)
{
    // Every patch read "corrupt payload", and a build said "internal error: a patch just
    // encoded does not decode": the reason (HTJ2K decoding is off by default) was lost.
    test::ScratchDir dir;
    const std::string arc = dir.path("htj2k.ridge");
    const std::string build = "build '" + test::dataPath("everest_crop.tif") + "' -o '" + arc +
                              "' --patch 33 --codec jpeg2000,library=htj2k --max-error 2 -q";
    const test::CommandResult refused = test::runRidge(build);
    // A codec requirement the command line can check: a usage error before any work.
    EXPECT_EQ(refused.exit_code, 2) << refused.output;
    EXPECT_NE(refused.output.find("RIDGE_ALLOW_HTJ2K=1"), std::string::npos) << refused.output;
    EXPECT_EQ(refused.output.find("internal error"), std::string::npos) << refused.output;
    ASSERT_EQ(test::runShell("RIDGE_ALLOW_HTJ2K=1 " + std::string(RIDGE_CLI_PATH) + " " + build)
                  .exit_code,
              0);
    const test::CommandResult verify = test::runRidge("verify '" + arc + "' -q");
    EXPECT_EQ(verify.exit_code, 1) << verify.output;
    EXPECT_NE(verify.output.find("its decoder is disabled: HTJ2K payloads are decoded only with "
                                 "RIDGE_ALLOW_HTJ2K=1"),
              std::string::npos)
        << verify.output;
    EXPECT_NE(verify.output.find("verify FAILED: 1 problem(s)"), std::string::npos)
        << verify.output;
    EXPECT_EQ(test::runShell("RIDGE_ALLOW_HTJ2K=1 " + std::string(RIDGE_CLI_PATH) + " verify '" +
                             arc + "' -q")
                  .exit_code,
              0);
}
