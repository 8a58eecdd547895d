// The command line's rough edges a GIS user met on real DEMs next to gdalinfo and
// gdal_translate (issue 22, item 4): codec requirements checked before any work, multi-band
// sources, float sources' quantization and type, what `info` says (NoData, band type, EPSG,
// vertical datum), the source's recorded name, the README's format version, and every
// `--help` listing only what its command takes. Inputs are made from the real fixtures with
// GDAL's own gdal_translate (gdal_utils.h).
#include "gdal_translate.h"
#include "test_support.h"

#include <gdal.h>
#include <gdal_utils.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <map>
#include <optional>
#include <regex>
#include <set>
#include <string>
#include <tuple>
#include <vector>

using namespace ridge;
namespace fs = std::filesystem;

namespace {

using test::gdalTranslate;

std::string inQuotes(const std::string& s)
{
    return "'" + s + "'";
}

struct Band {
    int width = 0, height = 0;
    std::string type;
    std::vector<double> values;
    std::optional<double> nodata;

    // The extremes of the samples that are not nodata.
    std::pair<double, double> validRange() const
    {
        double lo = INFINITY, hi = -INFINITY;
        for (const double v : values)
            if (!nodata || v != *nodata) {
                lo = std::min(lo, v);
                hi = std::max(hi, v);
            }
        return {lo, hi};
    }
};

Band readBand(const std::string& path, int band_number = 1)
{
    GDALAllRegister();
    Band b;
    GDALDatasetH ds = GDALOpen(path.c_str(), GA_ReadOnly);
    EXPECT_NE(ds, nullptr) << path;
    if (!ds)
        return b;
    GDALRasterBandH band = GDALGetRasterBand(ds, band_number);
    b.width = GDALGetRasterXSize(ds);
    b.height = GDALGetRasterYSize(ds);
    b.type = GDALGetDataTypeName(GDALGetRasterDataType(band));
    int has_nodata = 0;
    const double nodata = GDALGetRasterNoDataValue(band, &has_nodata);
    if (has_nodata)
        b.nodata = nodata;
    b.values.resize(size_t(b.width) * b.height);
    EXPECT_EQ(GDALRasterIO(band, GF_Read, 0, 0, b.width, b.height, b.values.data(), b.width,
                           b.height, GDT_Float64, 0, 0),
              CE_None);
    GDALClose(ds);
    return b;
}

nlohmann::json jsonOf(const test::CommandResult& r)
{
    EXPECT_EQ(r.exit_code, 0) << r.output;
    return nlohmann::json::parse(r.output, nullptr, false);
}

bool contains(const std::string& text, const std::string& phrase)
{
    return text.find(phrase) != std::string::npos;
}

} // namespace

// `--codec jpeg2000` without `--max-error` ran to 30 % and failed with status 1; the README
// promises status 2 for a command line that is wrong, before any work.
TEST(CliEdges, CodecRequirementsAreCheckedBeforeAnyWork)
{
    test::ScratchDir dir;
    const std::string src = inQuotes(test::dataPath("everest_crop.tif"));
    const std::string out = dir.path("out.ridge");
    struct Case {
        std::string args, phrase;
    };
    const std::vector<Case> cases = {
        {"--codec jpeg2000", "--max-error"},
        {"--codec progressive", "--max-error"},
        {"--codec progressive-paper", "--max-error"},
        {"--codec jpeg2000 --criterion rms", "--max-error"},
        {"--codec jpeg2001 --max-error 1", "--codec jpeg2001: not a codec (available: lossless"},
        {"--codec progressive,nested=99 --max-error 1", "--codec progressive,nested=99"},
        {"--codec jpeg2000,library=htj2k --max-error 1", "RIDGE_ALLOW_HTJ2K=1"},
        {"--codec progressive --criterion rms --max-error 1",
         "--criterion rms: the progressive codec's options are"},
        {"--codec lossless,level=9", "--codec lossless,level=9: the lossless codec takes no"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.args);
        const test::CommandResult r =
            test::runShell("env -u RIDGE_ALLOW_HTJ2K " + std::string(RIDGE_CLI_PATH) + " build " +
                           src + " -o " + inQuotes(out) + " " + c.args);
        EXPECT_EQ(r.exit_code, 2) << r.output;
        EXPECT_TRUE(contains(r.output, c.phrase)) << r.output;
        EXPECT_FALSE(contains(r.output, "0...10")) << "work started before the check: " << r.output;
        EXPECT_FALSE(fs::exists(out));
    }
    // What the check lets through builds.
    const test::CommandResult ok = test::runRidge("build " + src + " -o " + inQuotes(out) +
                                                  " -q --codec jpeg2000 --max-error 2");
    EXPECT_EQ(ok.exit_code, 0) << ok.output;
}

// An RGB JPEG was read as band 1 without a word; gdal_translate's -b chooses the band.
TEST(CliEdges, AMultiBandSourceNamesTheBandItReadsAndMinusBChoosesAnother)
{
    test::ScratchDir dir;
    const std::string jpeg = dir.path("everest_rgb.jpg");
    // Three different bands from the real heights: red rising with height, green falling,
    // blue a narrower stretch.
    gdalTranslate(test::dataPath("everest_crop.tif"), jpeg,
                  {"-of", "JPEG",     "-ot",      "Byte", "-b",   "1",   "-b",       "1",    "-b",
                   "1",   "-scale_1", "3369",     "8840", "0",    "255", "-scale_2", "3369", "8840",
                   "255", "0",        "-scale_3", "5000", "7000", "0",   "255"});
    ASSERT_EQ(GDALGetRasterCount(GDALOpen(jpeg.c_str(), GA_ReadOnly)), 3); // leaks a handle: fine

    const std::string first = dir.path("first.ridge");
    test::CommandResult r = test::runRidge("build " + inQuotes(jpeg) + " -o " + inQuotes(first));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_TRUE(contains(r.output, "warning")) << r.output;
    EXPECT_TRUE(contains(r.output, "3 bands (Red, Green, Blue)")) << r.output;
    EXPECT_TRUE(contains(r.output, "band 1 (Red)")) << r.output;
    EXPECT_TRUE(contains(r.output, "-b BAND")) << r.output;

    const std::string second = dir.path("second.ridge");
    r = test::runRidge("build " + inQuotes(jpeg) + " -o " + inQuotes(second) + " -b 2");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_FALSE(contains(r.output, "warning")) << "the band was chosen: " << r.output;

    // The archive holds band 2's heights exactly (lossless): its extremes are band 2's, and
    // verify reads band 2 of the source to check every sample.
    // (The JPEG inherits the Int16 source's nodata, clipped to 0: those samples are voids.)
    const auto [r_lo, r_hi] = readBand(jpeg, 1).validRange();
    const auto [g_lo, g_hi] = readBand(jpeg, 2).validRange();
    ASSERT_NE(std::pair(r_lo, r_hi), std::pair(g_lo, g_hi)) << "bands 1 and 2 must differ";
    for (const auto& [archive, lo, hi, band] :
         {std::tuple{first, r_lo, r_hi, 1}, std::tuple{second, g_lo, g_hi, 2}}) {
        const nlohmann::json info =
            jsonOf(test::runRidgeStdout("info " + inQuotes(archive) + " --json"));
        EXPECT_EQ(info["metadata"]["source"]["min_metres"].get<double>(), lo);
        EXPECT_EQ(info["metadata"]["source"]["max_metres"].get<double>(), hi);
        EXPECT_EQ(info["bands"][0]["band"], band);
        EXPECT_EQ(info["bands"][0]["type"], "Byte");
        const test::CommandResult v =
            test::runRidge("verify " + inQuotes(archive) + " -q --source " + inQuotes(jpeg));
        EXPECT_EQ(v.exit_code, 0) << v.output;
    }
    EXPECT_TRUE(contains(test::runRidge("info " + inQuotes(second)).output, "Band 2 Type=Byte"));

    // An uncompressed three-band GeoTIFF (gdal_translate's default): read without GDAL 3.6's
    // threaded-decoding noise ("Bad value 2 for ExtraSamples tag" for every block).
    const std::string tif = dir.path("everest_3band.tif");
    gdalTranslate(test::dataPath("everest_crop.tif"), tif, {"-b", "1", "-b", "1", "-b", "1"});
    r = test::runRidge("build " + inQuotes(tif) + " -o " + inQuotes(dir.path("tif.ridge")) +
                       " -b 3");
    EXPECT_EQ(r.exit_code, 0) << r.output;
    EXPECT_FALSE(contains(r.output, "ERROR")) << r.output;

    // A band the raster lacks: a usage error before any work, naming the count.
    r = test::runRidge("build " + inQuotes(jpeg) + " -o " + inQuotes(dir.path("x.ridge")) +
                       " -b 4");
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_TRUE(contains(r.output, "-b 4")) << r.output;
    EXPECT_TRUE(contains(r.output, "3 bands")) << r.output;
    EXPECT_FALSE(fs::exists(dir.path("x.ridge")));
    r = test::runRidge("build " + inQuotes(jpeg) + " -o " + inQuotes(dir.path("x.ridge")) +
                       " -b 0");
    EXPECT_EQ(r.exit_code, 2) << r.output;
}

// A Float32 source built "lossless" is quantized to 16-bit codes: build and info say to what
// step, and extract gives it back as Float32 (it came back as Float64, 33 of 262,144 samples
// equal to the source).
TEST(CliEdges, AFloatSourceStatesItsQuantizationStepAndExtractsToItsOwnType)
{
    test::ScratchDir dir;
    const std::string f32 = dir.path("everest_f32.tif");
    // The real heights as Float32 with a fractional scale: 100 .. 217.5 m.
    gdalTranslate(test::dataPath("everest_crop.tif"), f32,
                  {"-ot", "Float32", "-scale", "3369", "8840", "100", "217.5"});
    const Band source = readBand(f32);
    ASSERT_EQ(source.type, "Float32");
    const std::string arc = dir.path("f32.ridge");

    const nlohmann::json built =
        jsonOf(test::runRidgeStdout("build " + inQuotes(f32) + " -o " + inQuotes(arc) + " --json"));
    const double step = 117.5 / 65535.0; // the range over the codes
    EXPECT_EQ(built["data_type"], "Float32");
    EXPECT_EQ(built["exact"], false);
    EXPECT_NEAR(built["quantization_step"].get<double>(), step, 1e-9);
    fs::remove(arc);
    const test::CommandResult text =
        test::runRidge("build " + inQuotes(f32) + " -o " + inQuotes(arc));
    ASSERT_EQ(text.exit_code, 0) << text.output;
    EXPECT_TRUE(contains(text.output, "a step of 1.79 mm")) << text.output;

    const test::CommandResult info = test::runRidge("info " + inQuotes(arc));
    EXPECT_TRUE(contains(info.output, "Float32 heights to a step of 1.79 mm")) << info.output;
    const nlohmann::json info_json =
        jsonOf(test::runRidgeStdout("info " + inQuotes(arc) + " --json"));
    EXPECT_NEAR(info_json["quantization_step"].get<double>(), step, 1e-9);
    EXPECT_EQ(info_json["exact"], false);

    // The source's type by default, each sample within half a step (and Float32's own
    // rounding) of the source.
    const std::string out = dir.path("back.tif");
    const nlohmann::json extracted = jsonOf(
        test::runRidgeStdout("extract " + inQuotes(arc) + " -o " + inQuotes(out) + " --json"));
    EXPECT_EQ(extracted["type"], "Float32");
    EXPECT_EQ(extracted["type_reason"], "the source's type");
    const Band back = readBand(out);
    EXPECT_EQ(back.type, "Float32");
    ASSERT_EQ(back.values.size(), source.values.size());
    double worst = 0;
    for (size_t i = 0; i < back.values.size(); ++i)
        worst = std::max(worst, std::abs(back.values[i] - source.values[i]));
    EXPECT_LE(worst, step / 2 + 2e-5) << "a Float32 ulp at 217 m is 1.5e-5 m";
    EXPECT_GT(worst, 0.0) << "quantized, as build said";
}

// gdalinfo's NoData, band type and EPSG code, and the vertical datum from a compound CRS or
// from `build --vertical-datum`.
TEST(CliEdges, InfoSaysNoDataBandTypeEpsgAndVerticalDatum)
{
    test::ScratchDir dir;
    const std::string geo = dir.path("geo.ridge");
    ASSERT_EQ(test::runRidge("build " + inQuotes(test::dataPath("rainier_voids.tif")) + " -o " +
                             inQuotes(geo) + " -q")
                  .exit_code,
              0);
    std::string text = test::runRidge("info " + inQuotes(geo)).output;
    EXPECT_TRUE(contains(text, "Band 1 Type=Int16, NoData Value=-32768")) << text;
    EXPECT_TRUE(contains(text, "CRS: WGS 84 (EPSG:4326)")) << text;
    EXPECT_TRUE(contains(text, "Vertical datum: unknown")) << text;
    EXPECT_TRUE(contains(text, "--vertical-datum")) << "says how to record one: " << text;
    nlohmann::json j = jsonOf(test::runRidgeStdout("info " + inQuotes(geo) + " --json"));
    EXPECT_EQ(j["epsg"], 4326);
    EXPECT_EQ(j["bands"][0]["noDataValue"], -32768.0);
    EXPECT_EQ(j["bands"][0]["type"], "Int16");
    EXPECT_TRUE(j["vertical_datum"].is_null());

    const std::string utm = dir.path("utm.ridge");
    ASSERT_EQ(test::runRidge("build " + inQuotes(test::dataPath("everest_utm45.tif")) + " -o " +
                             inQuotes(utm) + " -q --vertical-datum EPSG:3855 --novshift")
                  .exit_code,
              0);
    text = test::runRidge("info " + inQuotes(utm)).output;
    EXPECT_TRUE(contains(text, "CRS: WGS 84 / UTM zone 45N (EPSG:32645)")) << text;
    EXPECT_TRUE(contains(text, "Vertical datum: EGM2008 height (EPSG:3855), from --vertical-datum"))
        << text;
    j = jsonOf(test::runRidgeStdout("info " + inQuotes(utm) + " --json"));
    EXPECT_EQ(j["epsg"], 32645);
    EXPECT_EQ(j["vertical_datum"]["epsg"], 3855);
    EXPECT_EQ(j["metadata"]["georeference"]["vertical_datum"]["name"], "EGM2008 height");

    // A compound CRS states its vertical datum itself.
    const std::string compound = dir.path("compound.tif");
    gdalTranslate(test::dataPath("everest_crop.tif"), compound, {"-a_srs", "EPSG:4326+5773"});
    const std::string cmp = dir.path("compound.ridge");
    ASSERT_EQ(
        test::runRidge("build " + inQuotes(compound) + " -o " + inQuotes(cmp) + " -q --novshift")
            .exit_code,
        0);
    text = test::runRidge("info " + inQuotes(cmp)).output;
    EXPECT_TRUE(contains(text, "Vertical datum: EGM96 height (EPSG:5773), from the source's CRS"))
        << text;
    // ... and by default its heights move to the ellipsoid (tests/io/geoid_shift_test.cpp).
    const std::string shifted = dir.path("shifted.ridge");
    ASSERT_EQ(test::runRidge("build " + inQuotes(compound) + " -o " + inQuotes(shifted) + " -q")
                  .exit_code,
              0);
    text = test::runRidge("info " + inQuotes(shifted)).output;
    EXPECT_TRUE(contains(text, "Vertical datum: WGS 84 ellipsoidal height, from EGM96 height "
                               "(EPSG:5773) shifted through"))
        << text;
    // verify --source shifts the source as the build did: every bound holds (N is about
    // −29 m at Everest, 700 times the archive's quantization error).
    const test::CommandResult verified =
        test::runRidge("verify " + inQuotes(shifted) + " --source " + inQuotes(compound));
    EXPECT_EQ(verified.exit_code, 0) << verified.output;

    // A name PROJ knows takes its EPSG spelling and code; one it does not is kept as given.
    ASSERT_EQ(test::runRidge("build " + inQuotes(compound) + " -o " +
                             inQuotes(dir.path("n.ridge")) +
                             " -q --vertical-datum 'egm2008 height' --novshift")
                  .exit_code,
              0);
    EXPECT_TRUE(contains(test::runRidge("info " + inQuotes(dir.path("n.ridge"))).output,
                         "Vertical datum: EGM2008 height (EPSG:3855), from --vertical-datum"));
    ASSERT_EQ(test::runRidge("build " + inQuotes(compound) + " -o " +
                             inQuotes(dir.path("l.ridge")) +
                             " -q --vertical-datum 'Khumbu survey datum'")
                  .exit_code,
              0);
    EXPECT_TRUE(contains(test::runRidge("info " + inQuotes(dir.path("l.ridge"))).output,
                         "Vertical datum: Khumbu survey datum, from --vertical-datum"));

    // Codes that are not vertical CRSs, or no CRS at all: usage errors, before any work.
    for (const std::string bad : {"EPSG:4326", "999999", "''"}) {
        const test::CommandResult r =
            test::runRidge("build " + inQuotes(compound) + " -o " + inQuotes(dir.path("x.ridge")) +
                           " --vertical-datum " + bad);
        EXPECT_EQ(r.exit_code, 2) << bad << ": " << r.output;
        EXPECT_TRUE(contains(r.output, "--vertical-datum")) << r.output;
        EXPECT_FALSE(contains(r.output, "0...10")) << r.output;
    }
}

// The archive stored the source's absolute path (the builder's directories); it records the
// name as given, an absolute path reduced to its file name.
TEST(CliEdges, TheArchiveRecordsTheSourcesNameNotAnAbsolutePath)
{
    test::ScratchDir dir;
    const std::string absolute = test::dataPath("everest_crop.tif");
    ASSERT_TRUE(fs::path(absolute).is_absolute());
    const std::string arc = dir.path("abs.ridge");
    ASSERT_EQ(
        test::runRidge("build " + inQuotes(absolute) + " -o " + inQuotes(arc) + " -q").exit_code,
        0);
    nlohmann::json j = jsonOf(test::runRidgeStdout("info " + inQuotes(arc) + " --json"));
    EXPECT_EQ(j["metadata"]["source"]["path"], "everest_crop.tif");
    EXPECT_FALSE(contains(test::readFile(arc), fs::path(absolute).parent_path().string()))
        << "the builder's directory is nowhere in the archive";

    fs::create_directory(dir.path("dem"));
    fs::copy_file(absolute, dir.path("dem/everest.tif"));
    const test::CommandResult r =
        test::runShell("cd " + inQuotes(dir.dir().string()) + " && " + RIDGE_CLI_PATH +
                       " build dem/everest.tif -o rel.ridge -q");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    j = jsonOf(test::runRidgeStdout("info " + inQuotes(dir.path("rel.ridge")) + " --json"));
    EXPECT_EQ(j["metadata"]["source"]["path"], "dem/everest.tif");
    EXPECT_TRUE(contains(test::runRidge("info " + inQuotes(dir.path("rel.ridge"))).output,
                         "Source: dem/everest.tif"));
}

// The README said format version 2 where `info` says 3: the README, docs/FORMAT.md and what
// the writer writes agree.
TEST(CliEdges, TheReadmeAndFormatDocStateTheVersionInfoReports)
{
    test::ScratchDir dir;
    const std::string arc = test::buildEverestWithCli(dir, "v.ridge", "");
    const int written =
        jsonOf(test::runRidgeStdout("info " + inQuotes(arc) + " --json"))["format_version"]
            .get<int>();
    const fs::path root = fs::path(RIDGE_TEST_DATA_DIR).parent_path().parent_path();
    const std::string readme = test::readFile((root / "README.md").string());
    const std::string format = test::readFile((root / "docs/FORMAT.md").string());
    ASSERT_FALSE(readme.empty());
    ASSERT_FALSE(format.empty());
    std::smatch m;
    ASSERT_TRUE(
        std::regex_search(readme, m, std::regex(R"(format is versioned \(currently (\d+))")))
        << "README's Compatibility section states the current version";
    EXPECT_EQ(std::stoi(m[1]), written);
    ASSERT_TRUE(std::regex_search(format, m, std::regex(R"(Writers write version (\d+))")));
    EXPECT_EQ(std::stoi(m[1]), written);
}

namespace {

// The flags a help page names: "--word" and "-w" tokens not inside a word. A token right after
// another command's name ("as render --camera takes them") or after a GDAL tool's
// ("gdal_translate -projwin") is that command's; `owner` says which command each belongs to.
std::vector<std::pair<std::string, std::string>> flagsNamed(const std::string& help,
                                                            const std::string& command,
                                                            const std::set<std::string>& commands)
{
    std::vector<std::pair<std::string, std::string>> flags;
    const std::regex token(R"((^|[^A-Za-z0-9_\-])(--?[A-Za-z][A-Za-z0-9_\-]*))");
    const std::regex word(R"(([A-Za-z0-9_\-]+)\s*$)");
    std::string current_section;
    size_t line_start = 0;
    while (line_start < help.size()) {
        const size_t line_end = std::min(help.find('\n', line_start), help.size());
        const std::string line = help.substr(line_start, line_end - line_start);
        line_start = line_end + 1;
        if (!line.empty() && line.back() == ':' && line[0] != ' ')
            current_section = line;
        // The top level's subcommand list: each line's flags are that command's.
        std::string owner = command;
        if (current_section == "Subcommands:") {
            std::smatch first;
            const std::string trimmed = line.substr(line.find_first_not_of(' ') == std::string::npos
                                                        ? line.size()
                                                        : line.find_first_not_of(' '));
            if (std::regex_search(trimmed, first, std::regex(R"(^([a-z\-]+))")) &&
                commands.count(first[1]))
                owner = first[1];
        }
        for (auto it = std::sregex_iterator(line.begin(), line.end(), token);
             it != std::sregex_iterator(); ++it) {
            const std::string flag = (*it)[2];
            const std::string before = line.substr(0, size_t(it->position(2)));
            std::smatch w;
            std::string flag_owner = owner;
            if (std::regex_search(before, w, word)) {
                if (commands.count(w[1]) && w[1] != command)
                    flag_owner = w[1];
                else if (std::string(w[1]).rfind("gdal", 0) == 0)
                    flag_owner = "gdal";
            }
            if (flag_owner != "gdal")
                flags.emplace_back(flag_owner, flag);
        }
    }
    return flags;
}

} // namespace

// `view --help` offered a --json it does not take (the top level's footer, inherited). Every
// flag any help page names must be accepted by the command it belongs to.
TEST(CliEdges, EveryHelpListsOnlyWhatItsCommandTakes)
{
    const test::CommandResult top = test::runRidge("--help");
    ASSERT_EQ(top.exit_code, 0) << top.output;
    // The commands: the top level's "Subcommands:" list.
    std::set<std::string> commands;
    {
        const size_t at = top.output.find("Subcommands:");
        ASSERT_NE(at, std::string::npos) << top.output;
        const std::regex entry(R"(\n  ([a-z][a-z\-]*) )");
        const std::string list = top.output.substr(at);
        for (auto it = std::sregex_iterator(list.begin(), list.end(), entry);
             it != std::sregex_iterator(); ++it)
            commands.insert((*it)[1]);
    }
    ASSERT_GE(commands.size(), 10u) << top.output;
    std::map<std::string, std::string> pages = {{"", top.output}};
    for (const std::string& c : commands) {
        const test::CommandResult r = test::runRidge(c + " --help");
        ASSERT_EQ(r.exit_code, 0) << c << ": " << r.output;
        pages[c] = r.output;
    }
    std::set<std::pair<std::string, std::string>> checked;
    for (const auto& [command, page] : pages)
        for (const auto& [owner, flag] : flagsNamed(page, command, commands)) {
            if (!checked.insert({owner, flag}).second)
                continue;
            // Given alone, a flag the command takes fails on something else (a missing
            // argument or value); one it does not take is named as unknown.
            const test::CommandResult r = test::runRidge(owner + " " + flag);
            EXPECT_FALSE(contains(r.output, "unknown option") || contains(r.output, "not expected"))
                << "`ridge " << (command.empty() ? "" : command + " ") << "--help` names " << flag
                << ", which `ridge " << owner << "` refuses: " << r.output;
        }
    EXPECT_GE(checked.size(), 100u) << "the walk found too few flags to mean anything";
    // The JSON convention is stated where --json is taken, and only there.
    EXPECT_TRUE(contains(pages["render"], "--json prints"));
    EXPECT_FALSE(contains(pages["view"], "--json"));
    EXPECT_FALSE(contains(pages["hillshade"], "--json"));
}
