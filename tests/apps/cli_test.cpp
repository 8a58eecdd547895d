// The `ridge` command line as a user runs it: exit codes, messages, outputs.
#include "test_support.h"

#include <gdal.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <vector>

using namespace ridge;
namespace fs = std::filesystem;

namespace {

// Writes a small single-band GeoTIFF with GDAL; `nodata` is set when given.
void writeTiff(const std::string& path, int w, int h, GDALDataType type,
               const std::vector<double>& values, std::optional<double> nodata = std::nullopt)
{
    GDALAllRegister();
    GDALDatasetH ds =
        GDALCreate(GDALGetDriverByName("GTiff"), path.c_str(), w, h, 1, type, nullptr);
    ASSERT_NE(ds, nullptr);
    GDALRasterBandH band = GDALGetRasterBand(ds, 1);
    if (nodata)
        GDALSetRasterNoDataValue(band, *nodata);
    std::vector<double> v = values;
    ASSERT_EQ(GDALRasterIO(band, GF_Write, 0, 0, w, h, v.data(), w, h, GDT_Float64, 0, 0), CE_None);
    GDALClose(ds);
}

// Every bad input: non-zero exit, a message naming the file, and no output file.
void expectRejected(const test::ScratchDir& dir, const std::string& input,
                    const std::string& phrase, const std::string& extra = "",
                    std::string names = "")
{
    if (names.empty())
        names = input;
    const std::string out = dir.path("out.ridge");
    const test::CommandResult r =
        test::runRidge("build '" + input + "' -o '" + out + "' -q " + extra);
    EXPECT_NE(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find(names), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(phrase), std::string::npos)
        << "expected '" << phrase << "' in: " << r.output;
    EXPECT_EQ(r.output.find("Segmentation"), std::string::npos);
    for (const auto& entry : fs::directory_iterator(dir.dir()))
        EXPECT_NE(entry.path().filename().string().rfind("out.ridge", 0), 0u)
            << "left behind: " << entry.path();
}

} // namespace

TEST(Cli, BuildInfoVerifyExtractHillshadeOnRealTerrain)
{
    test::ScratchDir dir;
    const std::string src = test::dataPath("everest_crop.tif");
    const std::string arc = dir.path("everest.ridge");
    test::CommandResult r = test::runRidge("build '" + src + "' -o '" + arc + "'");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("100 - done."), std::string::npos) << "GDAL-style progress on stderr";

    r = test::runRidge("info '" + arc + "' --json");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const nlohmann::json info = nlohmann::json::parse(r.output);
    EXPECT_EQ(info["codec"], "lossless");
    EXPECT_EQ(info["patch_size"], 129);
    EXPECT_TRUE(info["metadata"]["georeference"]["geographic"].get<bool>());
    EXPECT_EQ(info["levels"].size(), info["level_count"].get<size_t>());

    r = test::runRidge("info '" + arc + "'");
    ASSERT_EQ(r.exit_code, 0);
    EXPECT_NE(r.output.find("WGS 84"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("Bytes ("), std::string::npos) << "only with --bytes";
    r = test::runRidge("info '" + arc + "' --bytes");
    ASSERT_EQ(r.exit_code, 0);
    EXPECT_NE(r.output.find("level 0 codec payloads"), std::string::npos) << r.output;
    r = test::runRidge("info '" + arc + "' --bytes --json");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const nlohmann::json bytes = nlohmann::json::parse(r.output)["bytes"];
    EXPECT_EQ(bytes["header"], 160);
    EXPECT_EQ(bytes["levels"].size(), info["level_count"].get<size_t>());

    r = test::runRidge("verify '" + arc + "' --source '" + src + "' -q");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("OK"), std::string::npos);

    // Extract the finest level: the GeoTIFF must equal the source sample for sample and
    // carry the same geotransform.
    const std::string tif = dir.path("finest.tif");
    r = test::runRidge("extract '" + arc + "' -o '" + tif + "' -q");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    GDALAllRegister();
    GDALDatasetH a = GDALOpen(src.c_str(), GA_ReadOnly), b = GDALOpen(tif.c_str(), GA_ReadOnly);
    ASSERT_TRUE(a && b);
    const int w = GDALGetRasterXSize(a), h = GDALGetRasterYSize(a);
    ASSERT_EQ(GDALGetRasterXSize(b), w);
    std::vector<double> va(w * h), vb(w * h);
    ASSERT_EQ(GDALRasterIO(GDALGetRasterBand(a, 1), GF_Read, 0, 0, w, h, va.data(), w, h,
                           GDT_Float64, 0, 0),
              CE_None);
    ASSERT_EQ(GDALRasterIO(GDALGetRasterBand(b, 1), GF_Read, 0, 0, w, h, vb.data(), w, h,
                           GDT_Float64, 0, 0),
              CE_None);
    EXPECT_EQ(va, vb);
    double ga[6], gb[6];
    GDALGetGeoTransform(a, ga);
    GDALGetGeoTransform(b, gb);
    for (int k = 0; k < 6; ++k)
        EXPECT_DOUBLE_EQ(ga[k], gb[k]);
    GDALClose(a);
    GDALClose(b);

    // A window of a coarser level: pixel size doubles, centre of pixel (0,0) stays on sample (2x,
    // 2y).
    const std::string win = dir.path("window.tif");
    r = test::runRidge("extract '" + arc + "' --level 0 --srcwin 10 5 40 30 -o '" + win + "' -q");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    GDALDatasetH c = GDALOpen(win.c_str(), GA_ReadOnly);
    ASSERT_TRUE(c);
    EXPECT_EQ(GDALGetRasterXSize(c), 40);
    double gc[6];
    GDALGetGeoTransform(c, gc);
    const int64_t step = info["levels"][0]["step"].get<int64_t>();
    EXPECT_NEAR(gc[1], ga[1] * step, 1e-12);
    EXPECT_NEAR(gc[0] + 0.5 * gc[1], ga[0] + (10 * step + 0.5) * ga[1], 1e-9);
    GDALClose(c);

    const std::string png = dir.path("shade.png");
    r = test::runRidge("hillshade '" + arc + "' -o '" + png + "' -q");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    GDALDatasetH p = GDALOpen(png.c_str(), GA_ReadOnly);
    ASSERT_TRUE(p);
    EXPECT_EQ(GDALGetRasterXSize(p), w);
    EXPECT_EQ(GDALGetRasterCount(p), 3);
    GDALClose(p);
    EXPECT_EQ(test::temporariesIn(dir.dir()), std::vector<std::string>{});
}

TEST(Cli, BadInputsGetAClearErrorANonZeroExitAndNoOutput)
{
    test::ScratchDir dir;
    expectRejected(dir, dir.path("does-not-exist.tif"), "does-not-exist");

    const std::string garbage = dir.path("garbage.tif");
    std::ofstream(garbage) << "definitely not a raster\n";
    expectRejected(dir, garbage, "garbage");

    const std::string tiny = dir.path("tiny.tif");
    writeTiff(tiny, 1, 5, GDT_Int16, {1, 2, 3, 4, 5});
    expectRejected(dir, tiny, "2x2");

    const std::string voids = dir.path("all-nodata.tif");
    writeTiff(voids, 4, 4, GDT_Int16, std::vector<double>(16, -32768), -32768);
    expectRejected(dir, voids, "nodata");

    const std::string nan = dir.path("nan.tif");
    std::vector<double> values(16, 10.0);
    values[6] = std::numeric_limits<double>::quiet_NaN();
    writeTiff(nan, 4, 4, GDT_Float32, values);
    expectRejected(dir, nan, "(2, 1)");

    const std::string vrt = dir.path("no-bands.vrt");
    std::ofstream(vrt) << "<VRTDataset rasterXSize=\"10\" rasterYSize=\"10\"></VRTDataset>\n";
    expectRejected(dir, vrt, "band");

    expectRejected(dir, test::dataPath("everest_crop.tif"), "not 2^n+1", "--patch 100",
                   "--patch 100");
    expectRejected(dir, test::dataPath("everest_crop.tif"), "power of two", "--block 6",
                   "--block 6");
}

TEST(Cli, VerifyFailsWithExitCodeOneOnACorruptArchive)
{
    test::ScratchDir dir;
    const std::string arc = test::buildEverestWithCli(dir, "a.ridge", "--patch 65");
    {
        std::fstream f(arc, std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(static_cast<std::streamoff>(fs::file_size(arc) / 2));
        f.put('\x42');
    }
    const test::CommandResult r = test::runRidge("verify '" + arc + "' -q");
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_NE(r.output.find("patch (level"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("checksum"), std::string::npos) << r.output;
}

// Exit statuses, as README.md documents them: 0 success, 1 failure, 2 usage.
TEST(Cli, UsageErrorsExitWithTwo)
{
    EXPECT_EQ(test::runRidge("").exit_code, 2);
    EXPECT_EQ(test::runRidge("build").exit_code, 2);
    EXPECT_EQ(test::runRidge("info").exit_code, 2);
    EXPECT_EQ(test::runRidge("frobnicate").exit_code, 2);
    EXPECT_EQ(test::runRidge("info a.ridge --no-such-flag").exit_code, 2);
    EXPECT_EQ(test::runRidge("hillshade a.ridge -o x.png --level x").exit_code, 2);
    EXPECT_EQ(test::runRidge("--version").exit_code, 0);
    EXPECT_EQ(test::runRidge("--help").exit_code, 0);
    EXPECT_EQ(test::runRidge("build --help").exit_code, 0);
    // A well-formed command line whose input is missing fails while running: 1.
    test::ScratchDir dir;
    EXPECT_EQ(test::runRidge("info '" + dir.path("missing.ridge") + "'").exit_code, 1);
}

// A mistyped command or flag is named, with the nearest valid spelling.
TEST(Cli, AnUnknownCommandOrFlagIsNamedWithTheNearestValidOne)
{
    struct Case {
        std::string args, phrase;
    };
    for (const Case& c :
         {Case{"biuld x", "unknown command 'biuld'; did you mean 'build'?"},
          Case{"rendr x -o y.png", "unknown command 'rendr'; did you mean 'render'?"},
          Case{"frobnicate", "unknown command 'frobnicate' (ridge --help lists the commands)"},
          Case{"bench a.ridge --frams 3", "ridge bench: unknown option '--frams'; did you mean "
                                          "'--frames'?"},
          Case{"info a.ridge --jsno",
               "ridge info: unknown option '--jsno'; did you mean '--json'?"},
          Case{"build x -o y --z-ofset=3",
               "unknown option '--z-ofset'; did you mean '--z-offset'?"},
          Case{"build x -o y --z-offset -5 --quuux", "ridge build: unknown option '--quuux' ("},
          Case{"extract a.ridge -o x.tif --projwim 1 2 3 4",
               "unknown option '--projwim'; did you mean '--projwin'?"}}) {
        const test::CommandResult r = test::runRidge(c.args);
        EXPECT_EQ(r.exit_code, 2) << c.args << ": " << r.output;
        EXPECT_NE(r.output.find(c.phrase), std::string::npos)
            << c.args << ": expected '" << c.phrase << "' in: " << r.output;
    }
}

// One --json convention: the flag prints one JSON document on stdout and nothing else there
// (human text goes to stderr or is not printed); --json-file PATH writes the document instead.
TEST(Cli, JsonPrintsOneDocumentOnStdoutInEveryCommand)
{
    test::ScratchDir dir;
    const std::string src = test::dataPath("everest_crop.tif");
    const std::string arc = dir.path("e.ridge");
    struct Case {
        std::string args, key;
    };
    for (const Case& c :
         {Case{"build '" + src + "' -o '" + arc + "' --patch 65 --json", "patch_count"},
          Case{"info '" + arc + "' --json", "level_count"},
          Case{"verify '" + arc + "' --json", "patches_checked"},
          Case{"extract '" + arc + "' -o '" + dir.path("x.tif") + "' --json", "geotransform"},
          Case{"bench '" + arc + "' --frames 2 --size 32x24 --json", "frames"}}) {
        const test::CommandResult r = test::runRidgeStdout(c.args);
        ASSERT_EQ(r.exit_code, 0) << c.args << ": " << r.output;
        nlohmann::json j;
        ASSERT_NO_THROW(j = nlohmann::json::parse(r.output)) << c.args << ": " << r.output;
        EXPECT_TRUE(j.contains(c.key)) << c.args << ": " << r.output;
    }
    // The same document as a file, for commands whose human report is worth keeping on stdout.
    const std::string file = dir.path("bench.json");
    const test::CommandResult r = test::runRidgeStdout(
        "bench '" + arc + "' --frames 2 --size 32x24 --json-file '" + file + "'");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("fps"), std::string::npos) << "the summary stays on stdout";
    EXPECT_EQ(nlohmann::json::parse(test::readFile(file))["frames"].size(), 2u);
}

// One spelling per concept: hillshade takes the sun as render does (--sun AZ,ALT); the older
// spellings (hillshade --azimuth/--altitude, bench --renderer, extract --window) still work
// but are hidden from --help.
TEST(Cli, OneSpellingPerConceptWithTheOldOnesHidden)
{
    test::ScratchDir dir;
    const std::string arc = test::buildEverestWithCli(dir, "e.ridge", "--patch 65");
    const std::string a = dir.path("sun.png"), b = dir.path("az.png");
    ASSERT_EQ(test::runRidge("hillshade '" + arc + "' -o '" + a + "' -q --sun 200,30").exit_code,
              0);
    ASSERT_EQ(
        test::runRidge("hillshade '" + arc + "' -o '" + b + "' -q --azimuth 200 --altitude 30")
            .exit_code,
        0);
    EXPECT_TRUE(test::readFile(a) == test::readFile(b));
    const std::string d = dir.path("default.png");
    ASSERT_EQ(test::runRidge("hillshade '" + arc + "' -o '" + d + "' -q").exit_code, 0);
    EXPECT_FALSE(test::readFile(a) == test::readFile(d)) << "--sun must change the light";
    const test::CommandResult bad =
        test::runRidge("hillshade '" + arc + "' -o '" + dir.path("x.png") + "' --sun 315,100");
    EXPECT_EQ(bad.exit_code, 2);
    EXPECT_NE(bad.output.find("--sun 100: the altitude must be a number in (0, 90]"),
              std::string::npos)
        << bad.output;
    struct Hidden {
        std::string command, shown, hidden;
    };
    for (const Hidden& h :
         {Hidden{"hillshade", "--sun", "--azimuth"}, Hidden{"bench", "--lod", "--renderer"},
          Hidden{"extract", "--srcwin", "--window"}}) {
        const std::string help = test::runRidge(h.command + " --help").output;
        EXPECT_NE(help.find(h.shown), std::string::npos) << help;
        EXPECT_EQ(help.find(h.hidden), std::string::npos) << help;
    }
}

TEST(Cli, FillVoidsKeepsTheWarpedCollarAndSaysHowManySamplesItKeptOrFilled)
{
    test::ScratchDir dir;
    const std::string src = test::dataPath("everest_utm44.tif");
    const std::string kept = dir.path("kept.ridge"), all = dir.path("all.ridge");
    test::CommandResult r = test::runRidge("build '" + src + "' -o '" + kept + "' --patch 33");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("0 voids filled, 5679 kept as nodata"), std::string::npos) << r.output;
    r = test::runRidge("build '" + src + "' -o '" + all + "' --patch 33 --fill-voids all");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("5679 voids filled, 0 kept as nodata"), std::string::npos) << r.output;
    // --json says the same (stdout alone is the document).
    r = test::runRidgeStdout("build '" + src + "' -o '" + dir.path("j.ridge") +
                             "' --patch 33 --json");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const nlohmann::json j = nlohmann::json::parse(r.output);
    EXPECT_EQ(j.at("voids_kept"), 5679);
    EXPECT_EQ(j.at("voids_filled"), 0);
    EXPECT_EQ(j.at("fill_voids"), "interior");
    r = test::runRidge("info '" + kept + "'");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("ridge format v6"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("0 voids filled, 5679 kept as nodata, --fill-voids interior"),
              std::string::npos)
        << r.output;
    r = test::runRidge("verify '" + kept + "' --source '" + src + "' -q");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("5679 void samples of the source skipped (no measurement there), "
                            "5679 of them kept as nodata"),
              std::string::npos)
        << r.output;
    r = test::runRidge("build '" + src + "' -o '" + dir.path("x.ridge") + "' --fill-voids some");
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.output.find("--fill-voids"), std::string::npos) << r.output;
    EXPECT_FALSE(std::filesystem::exists(dir.path("x.ridge")));
}
