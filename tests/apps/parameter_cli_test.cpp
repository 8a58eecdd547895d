// Numeric flags as a user mistypes them: NaN, infinities, zero budgets, absurd z-scales and a
// raster of 10^6 x 10^6 samples. A value its flag cannot take exits with the usage status 2,
// one the inputs cannot take (a z-scale that overflows this raster's heights, a raster too big
// for the memory) with the failure status 1; never a signal, never 0. Each says which flag or
// file and what range, in a line a person can read, and leaves nothing.
#include "test_support.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>

using namespace ridge;
namespace fs = std::filesystem;

namespace {

// 'path', for a command line.
std::string shellQuoted(const std::string& path)
{
    std::string q = "'";
    q += path;
    q += "'";
    return q;
}

class ParameterCli : public ::testing::Test {
  protected:
    static void SetUpTestSuite()
    {
        scratch_ = new test::ScratchDir();
        archive_ =
            new std::string(test::buildEverestWithCli(*scratch_, "everest.ridge", "--patch 33"));
    }
    static void TearDownTestSuite()
    {
        delete archive_;
        delete scratch_;
    }

    // Runs `ridge ARGS` (outputs are named out.* in the suite's directory) and checks the
    // promises: exit status `status` (2: usage, the default; 1: failure), every phrase in the
    // output, no absurdly long number, and no out.* file (or its temporary) left behind.
    static void expectRefused(const std::string& args, const std::vector<std::string>& phrases,
                              int status = kUsage)
    {
        const test::CommandResult r = test::runRidge(args); // a signal reads as 128 + n
        SCOPED_TRACE("ridge " + args);
        EXPECT_EQ(r.exit_code, status) << r.output;
        for (const std::string& p : phrases)
            EXPECT_NE(r.output.find(p), std::string::npos)
                << "expected '" << p << "' in: " << r.output;
        // (The scratch directory's random name is digits too.)
        std::string text = r.output;
        const std::string dir = scratch_->dir().string();
        for (size_t at; (at = text.find(dir)) != std::string::npos;)
            text.replace(at, dir.size(), "DIR");
        EXPECT_FALSE(std::regex_search(text, std::regex("[0-9]{20}")))
            << "a number nobody can read: " << r.output;
        EXPECT_LT(r.output.size(), 600u) << r.output;
        EXPECT_EQ(r.output.find("internal error"), std::string::npos) << r.output;
        for (const auto& entry : fs::directory_iterator(scratch_->dir()))
            EXPECT_EQ(entry.path().filename().string().rfind("out.", 0), std::string::npos)
                << "left behind: " << entry.path();
    }

    static constexpr int kUsage = 2, kFailure = 1;

    static std::string out(const std::string& name)
    {
        return shellQuoted(scratch_->path("out." + name));
    }
    static std::string arc() { return shellQuoted(*archive_); }

    static test::ScratchDir* scratch_;
    static std::string* archive_;
};

test::ScratchDir* ParameterCli::scratch_ = nullptr;
std::string* ParameterCli::archive_ = nullptr;

} // namespace

TEST_F(ParameterCli, RenderRefusesANanOrInfiniteCamera)
{
    const std::string render = "render " + arc() + " -o " + out("png") + " --size 64x64 ";
    expectRefused(render + "--camera nan,0,0",
                  {"--camera nan: each coordinate must be a number in [-1e+15, 1e+15]"});
    expectRefused(render + "--camera inf,0,0", {"--camera inf:"});
    expectRefused(render + "--camera 0,-inf,0", {"--camera -inf:"});
    expectRefused(render + "--camera 1e400,0,0", {"--camera 1e400:"});
    expectRefused(render + "--camera 1,2,3 --look-at 0,nan,0", {"--look-at nan:"});
}

TEST_F(ParameterCli, RenderRefusesNanEpsilonSunFovAndSamples)
{
    const std::string render = "render " + arc() + " -o " + out("png") + " --size 64x64 ";
    expectRefused(render + "--error nan", {"--error nan: must be a number in [0.05, 1000]"});
    expectRefused(render + "--texel-size nan", {"--texel-size nan: must be a number in [0, 1000]"});
    expectRefused(render + "--texel-size -1", {"--texel-size -1:"});
    expectRefused(render + "--sun nan,45",
                  {"--sun nan: the azimuth must be a number in [-360, 360]"});
    expectRefused(render + "--sun 315,nan",
                  {"--sun nan: the altitude must be a number in (0, 90]"});
    expectRefused(render + "--sun 315,0", {"--sun 0: the altitude"});
    expectRefused(render + "--fov nan", {"--fov nan: must be a number in [1, 170]"});
    expectRefused(render + "--samples 0", {"--samples 0: must be an integer in [1, 16]"});
    expectRefused("render " + arc() + " -o " + out("png") + " --size 20000x10",
                  {"--size 20000x10: each side must be an integer in [1, 16384]"});
}

TEST_F(ParameterCli, AZeroVramBudgetGetsAShortReadableRange)
{
    expectRefused("render " + arc() + " -o " + out("png") + " --size 64x64 --vram 0",
                  {"--vram 0: must be a number in (0, 1e+06]"});
    expectRefused("bench " + arc() + " --frames 2 --size 64x64 --vram 0",
                  {"--vram 0: must be a number in (0, 1e+06]"});
    expectRefused("bench " + arc() + " --frames 2 --size 64x64 --ram nan", {"--ram nan:"});
    expectRefused("bench " + arc() + " --frames 2 --size 64x64 --upload-ms inf",
                  {"--upload-ms inf:"});
    expectRefused("bench " + arc() + " --frames 2 --size 64x64 --upload-mb -1",
                  {"--upload-mb -1:"});
}

TEST_F(ParameterCli, BenchRefusesANanSpeedAndOtherBadNumbers)
{
    const std::string bench = "bench " + arc() + " --size 64x64 --json-file " + out("json") + " ";
    expectRefused(bench + "--frames 2 --speed nan",
                  {"--speed nan: must be a number in (0, 1e+06]"});
    expectRefused(bench + "--frames 2 --speed inf", {"--speed inf:"});
    expectRefused(bench + "--frames 2 --error nan", {"--error nan:"});
    expectRefused(bench + "--frames 2 --texel-size inf", {"--texel-size inf:"});
    expectRefused(bench + "--frames 0", {"--frames 0: must be an integer in [1, 100000000]"});
    // A scheme's own numbers are its --lod spec's: lod_spec_cli_test.cpp.
}

TEST_F(ParameterCli, BuildRefusesAZScaleThatMakesHeightsImpossibleAndWritesNothing)
{
    const std::string src = shellQuoted(test::dataPath("everest_crop.tif"));
    expectRefused("build " + src + " -o " + out("ridge") + " -q --z-scale 1e300",
                  {"everest_crop.tif", "z_scale 1e+300", "heights [-3.2768e+304, 3.2767e+304] m",
                   "z_scale is --z-scale"},
                  kFailure);
    expectRefused("build " + src + " -o " + out("ridge") + " -q --z-scale 0",
                  {"--z-scale 0: its magnitude must be a finite number >= 1e-09"});
    expectRefused("build " + src + " -o " + out("ridge") + " -q --z-scale nan", {"--z-scale nan:"});
    expectRefused("build " + src + " -o " + out("ridge") + " -q --z-offset inf",
                  {"--z-offset inf:"});
    expectRefused("build " + src + " -o " + out("ridge") + " -q --spacing nan",
                  {"--spacing nan: must be a number in (0, 1e+07]"});
}

TEST_F(ParameterCli, ProgressiveMaxErrorBelowZeroSaysItMustBePositive)
{
    const std::string src = shellQuoted(test::dataPath("everest_crop.tif"));
    expectRefused("build " + src + " -o " + out("ridge") + " -q --codec progressive --max-error -1",
                  {"--max-error -1: must be a number in (0, 1e+07]"});
    expectRefused("build " + src + " -o " + out("ridge") +
                      " -q --codec progressive --max-error nan",
                  {"--max-error nan:"});
}

TEST_F(ParameterCli, AMillionByAMillionRasterIsRefusedWithItsSizeAndTheMemoryItNeeds)
{
    const std::string vrt = scratch_->path("huge.vrt");
    std::ofstream(vrt) << "<VRTDataset rasterXSize=\"1000000\" rasterYSize=\"1000000\">\n"
                          "  <VRTRasterBand dataType=\"Int16\" band=\"1\"/>\n</VRTDataset>\n";
    const std::string build = "build " + shellQuoted(vrt) + " -o " + out("ridge") + " -q";
    // A small limit, so that the test does not depend on the machine ...
    expectRefused(build + " --max-memory 64",
                  {"huge.vrt: 1000000 x 1000000 samples need about ",
                   "GiB to build (streaming: ", "level L-1 in memory, 466 GiB",
                   "but 64.0 MiB are available", "memory_limit_bytes is --max-memory"},
                  kFailure);
    // ... and what the machine has.
    expectRefused(build, {"huge.vrt: 1000000 x 1000000 samples need about ", "are available ("},
                  kFailure);
    expectRefused(build + " --filter neville",
                  {"huge.vrt", "(in memory: ", "whole grid, 1.82 TiB", "Neville row pass"},
                  kFailure);
    expectRefused(build + " --max-memory 0", {"--max-memory 0: must be a number in (0, 1e+09]"});
    // The other commands that read a raster: verify --source compares sizes first, codec-bench
    // (which holds the raster) checks its memory like build.
    expectRefused("verify " + arc() + " --source " + shellQuoted(vrt) + " -q",
                  {"huge.vrt: size 1000000x1000000 differs"}, kFailure);
    expectRefused("codec-bench " + shellQuoted(vrt) + " -q",
                  {"huge.vrt: 1000000 x 1000000 samples need at least ", "to benchmark"}, kFailure);
}

TEST_F(ParameterCli, HillshadeExtractAndCodecBenchRefuseBadNumbersByFlag)
{
    expectRefused("hillshade " + arc() + " -o " + out("png") + " --azimuth nan",
                  {"--azimuth nan: must be a number in [-360, 360]"});
    expectRefused("hillshade " + arc() + " -o " + out("png") + " --altitude 100",
                  {"--altitude 100:"});
    expectRefused("hillshade " + arc() + " -o " + out("png") + " -z 0", {"--z-factor 0:"});
    expectRefused("hillshade " + arc() + " -o " + out("png") + " --level -5",
                  {"--level -5: must be an integer in [-1, 62]"});
    expectRefused("extract " + arc() + " -o " + out("tif") + " --srcwin 0 0 0 10",
                  {"--srcwin 0: XSIZE must be an integer in [1, 2147483647]"});
    // --window: the hidden alias kept for scripts, the same option.
    expectRefused("extract " + arc() + " -o " + out("tif") + " --window 0 0 0 10",
                  {"--srcwin 0: XSIZE must be an integer in [1, 2147483647]"});
    expectRefused("codec-bench " + shellQuoted(test::dataPath("everest_crop.tif")) +
                      " --max-error nan -q",
                  {"--max-error nan:"});
    expectRefused("codec-bench " + shellQuoted(test::dataPath("everest_crop.tif")) +
                      " --tile -1 -q",
                  {"--tile -1:"});
    expectRefused("view " + arc() + " --fov nan --frames 1", {"--fov nan:"});
}

// --- One rule per spelling and per range (issue 23) ------------------------------------------

TEST_F(ParameterCli, TheSunAltitudeIsInZeroToNinetyOpenAtZeroForHillshadeAsForRender)
{
    // hillshade accepted 0 (a sun on the horizon, nothing lit) where render refused it.
    expectRefused("hillshade " + arc() + " -o " + out("png") + " --sun 315,0",
                  {"--sun 0: the altitude must be a number in (0, 90]"});
    expectRefused("hillshade " + arc() + " -o " + out("png") + " --altitude 0",
                  {"--altitude 0: must be a number in (0, 90]"});
    expectRefused("render " + arc() + " -o " + out("png") + " --sun 315,0",
                  {"--sun 0: the altitude must be a number in (0, 90]"});
}

TEST_F(ParameterCli, CodecBenchStatesAndEnforcesAPositiveMaxError)
{
    // Its help allowed 0, which then failed after the work had started.
    const test::CommandResult help = test::runRidge("codec-bench --help");
    EXPECT_NE(help.output.find("a number in (0, 1e+07]"), std::string::npos) << help.output;
    expectRefused("codec-bench " + shellQuoted(test::dataPath("everest_crop.tif")) +
                      " --max-error 0 -q",
                  {"--max-error 0: must be a number in (0, 1e+07]"});
}

TEST_F(ParameterCli, HexadecimalAndOtherSpellingsAreRefusedByEveryNumberAlike)
{
    // --max-error 0x10 read as 16 while --patch 0x10 was refused: one rule now, decimal.
    const std::string tif = shellQuoted(test::dataPath("everest_crop.tif"));
    expectRefused("build " + tif + " -o " + out("ridge") + " --codec progressive --max-error 0x10",
                  {"--max-error 0x10: must be a number in (0, 1e+07]"});
    expectRefused("build " + tif + " -o " + out("ridge") + " --patch 0x10",
                  {"--patch 0x10: must be an integer in [5, 4097]"});
    expectRefused("build " + tif + " -o " + out("ridge") + " --z-offset ' 5'", {"--z-offset  5:"});
    expectRefused("query " + arc() + " 0x10 5 --pixel", {"x 0x10: must be a decimal number"});
    expectRefused("query " + arc() + " 5 1e3x --pixel", {"y 1e3x: must be a decimal number"});
    expectRefused("render " + arc() + " -o " + out("png") + " --size 0x40x32",
                  {"--size 0x40x32: expected WIDTHxHEIGHT"});
    expectRefused("render " + arc() + " -o " + out("png") + " --size ' 64x32'",
                  {"--size  64x32: expected WIDTHxHEIGHT"});
    expectRefused("render " + arc() + " -o " + out("png") + " --camera 0x1,0,100",
                  {"--camera 0x1:"});
    // Decimal spellings, exponents included, still work.
    EXPECT_EQ(test::runRidge("query " + arc() + " 1e1 +2.5 --pixel").exit_code, 0);
}

TEST_F(ParameterCli, ANegativeNumberSpeltWithALetterOrAPointIsANumberNotAFlag)
{
    // `query A 10 -inf` read -inf as the flags -i -n -f; -.5 likewise.
    const test::CommandResult inf = test::runRidge("query " + arc() + " 10 -inf --pixel");
    EXPECT_EQ(inf.exit_code, 1) << inf.output;
    EXPECT_NE(inf.output.find("10 -inf: error: pixel point is (10, -inf): every component must "
                              "be a finite number"),
              std::string::npos)
        << inf.output;
    const test::CommandResult half = test::runRidge("query " + arc() + " -.5 10 --pixel");
    EXPECT_NE(half.output.find("-0.5 10: off the raster"), std::string::npos) << half.output;
    // As a flag's value it was already a number, and stays one (refused by its range).
    expectRefused("hillshade " + arc() + " -o " + out("png") + " --z-factor -inf",
                  {"--z-factor -inf: must be a number in (0, 1e+06]"});
    // A file named like one is still a file.
    expectRefused("info -inf", {"-inf: No such file or directory"}, kFailure);
}

TEST_F(ParameterCli, ARenderTargetTheGlImplementationCannotAllocateIsAClearError)
{
    // 16384x16384 is within GL_MAX_RENDERBUFFER_SIZE on llvmpipe, but 4 samples of it are
    // not allocated: "framebuffer is incomplete (status 0x8cd6)" said nothing of why. Where
    // the implementation can (a large GPU), the frame is simply rendered.
    const test::CommandResult r =
        test::runRidge("render " + arc() + " -o " + out("png") + " --size 16384x16384 -q");
    fs::remove(scratch_->path("out.png"));
    if (r.exit_code == 0)
        GTEST_SKIP() << "this GL implementation renders 16384x16384 with 4 samples";
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_NE(r.output.find("a 16384x16384 render target with 4 sample(s) per pixel (8 GiB of "
                            "colour and depth) cannot be allocated by this GL implementation"),
              std::string::npos)
        << r.output;
    EXPECT_NE(r.output.find("use fewer samples or a smaller size"), std::string::npos) << r.output;
}
