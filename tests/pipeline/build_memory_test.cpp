// The build sizes itself before allocating: a raster it cannot hold is refused with the file,
// its size and the memory needed; the pipeline's options are range-checked by name.
#include "test_support.h"

#include "ridge/core/error.h"
#include "ridge/pipeline/build.h"
#include "ridge/pipeline/build_memory.h"
#include "ridge/pipeline/extract.h"
#include "ridge/pipeline/hillshade.h"

#include "error_expectations.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>

using namespace ridge;
namespace fs = std::filesystem;

namespace {

using ridge::test::errorOf;
using ridge::test::expectPhrases;

// An Int16 raster declaring `size` x `size` samples and holding none (a VRT without sources).
std::string hugeVrt(const test::ScratchDir& dir, int size)
{
    const std::string path = dir.path("huge.vrt");
    std::ofstream(path) << "<VRTDataset rasterXSize=\"" << size << "\" rasterYSize=\"" << size
                        << "\">\n  <VRTRasterBand dataType=\"Int16\" band=\"1\"/>\n</VRTDataset>\n";
    return path;
}

io::RasterProbe probeOf(int width, int height, bool direct = true)
{
    io::RasterProbe p;
    p.width = width;
    p.height = height;
    p.direct_codes = direct;
    p.strip_extra_bytes_per_sample = direct ? 0 : 8;
    p.block_cache_bytes = 4 << 20;
    return p;
}

const MemoryTerm* term(const BuildMemoryEstimate& e, const std::string& what)
{
    for (const MemoryTerm& t : e.terms)
        if (t.what == what)
            return &t;
    return nullptr;
}

} // namespace

TEST(BuildMemory, StreamingNeedsAQuarterOfTheGridNotTheGrid)
{
    const BuildOptions o;
    const io::RasterProbe p = probeOf(1000000, 1000000);
    const BuildMemoryEstimate s = estimateBuildMemory(p, o, true, false);
    ASSERT_TRUE(s.streaming);
    // Level L-1 of 10^6 x 10^6 at patches of 129: 500001 x 500001 samples of 2 bytes.
    ASSERT_NE(term(s, "level L-1 in memory"), nullptr);
    EXPECT_EQ(term(s, "level L-1 in memory")->bytes, uint64_t(500001) * 500001 * 2);
    EXPECT_EQ(s.terms.front().what, "level L-1 in memory") << "largest first";
    EXPECT_LT(s.total(), uint64_t(600) << 30);
    EXPECT_GT(s.total(), uint64_t(470) << 30);
    // Level L−1's water flags at 2 bits a sample beside it.
    EXPECT_NE(s.describe().find("streaming: level L-1 in memory, 466 GiB; sample flags, 58.7 GiB; "
                                "index and errors, "),
              std::string::npos)
        << s.describe();

    const BuildMemoryEstimate m = estimateBuildMemory(p, o, false, true);
    EXPECT_FALSE(m.streaming);
    EXPECT_GE(m.total(), uint64_t(1000000) * 1000000 * 3) << "grid and void mask at least";
    EXPECT_NE(m.describe().find("whole grid, 1.82 TiB"), std::string::npos) << m.describe();
    // Voids kept as nodata (the default, fill_voids interior) hold their 1 B/sample mask
    // beside the fill's (and, while encoding, the validity grids: 2 · 4/3 bits per sample);
    // the sample flags take 1 B/sample and their 2-bit grid.
    EXPECT_NE(m.describe().find("in memory: whole grid, 1.82 TiB; sample flags, 1.14 TiB; "
                                "void filling, 931 GiB; kept-nodata mask, 931 GiB"),
              std::string::npos)
        << m.describe();
    BuildOptions fill_all = o;
    fill_all.ingest.fill_voids = io::VoidFill::All;
    const BuildMemoryEstimate a = estimateBuildMemory(p, fill_all, false, true);
    EXPECT_NE(a.describe().find("in memory: whole grid, 1.82 TiB"), std::string::npos)
        << a.describe();
    EXPECT_EQ(a.describe().find("kept-nodata"), std::string::npos) << a.describe();
    EXPECT_LT(a.total(), m.total());
}

TEST(BuildMemory, NevilleAndProgressiveCostWhatTheyHold)
{
    const io::RasterProbe p = probeOf(4097, 4097);
    BuildOptions neville;
    neville.filter = PyramidFilter::Neville4;
    // The peak is the first coarsening: the grid, its rows filtered into floats, level L-1.
    const BuildMemoryEstimate n = estimateBuildMemory(p, neville, false, false);
    ASSERT_NE(term(n, "Neville row pass"), nullptr);
    EXPECT_EQ(term(n, "Neville row pass")->bytes, uint64_t(4097) * 2049 * 4);
    ASSERT_NE(term(n, "Neville levels"), nullptr);
    EXPECT_EQ(term(n, "Neville levels")->bytes, uint64_t(2049) * 2049 * 2);
    EXPECT_EQ(term(n, "whole grid")->bytes, uint64_t(4097) * 4097 * 2);
    BuildOptions progressive;
    progressive.codec = "progressive";
    progressive.max_error = 1.0;
    EXPECT_TRUE(buildStreams(progressive));
    // In memory (what a source with voids falls back to): while level 4 (16 x 16 patches) is
    // coded from level 3's 8 x 8, both are kept.
    const BuildMemoryEstimate r = estimateBuildMemory(p, progressive, false, false);
    ASSERT_NE(term(r, "progressive reconstructions"), nullptr);
    EXPECT_EQ(term(r, "progressive reconstructions")->bytes, uint64_t(256 + 64) * 129 * 129 * 2);
    // Streamed, the finest level is coded from level 4's codes: the most ever kept is while
    // level 3 is coded from level 2's 4 x 4 reconstructions, keeping its own 8 x 8 for level 4.
    const BuildMemoryEstimate s = estimateBuildMemory(p, progressive, true, false);
    ASSERT_NE(term(s, "progressive reconstructions"), nullptr);
    EXPECT_EQ(term(s, "progressive reconstructions")->bytes, uint64_t(16 + 64) * 129 * 129 * 2);
    EXPECT_EQ(term(s, "level L-1 in memory")->bytes, uint64_t(2049) * 2049 * 2);
    BuildOptions jpeg2000 = progressive;
    jpeg2000.codec = "jpeg2000";
    EXPECT_FALSE(buildStreams(jpeg2000)); // decodes down a chain of parents
}

TEST(BuildMemory, AMillionByAMillionRasterIsRefusedBeforeAnythingIsAllocated)
{
    test::ScratchDir dir;
    const std::string input = hugeVrt(dir, 1000000);
    const std::string out = dir.path("huge.ridge");
    BuildOptions o;
    o.memory_limit_bytes = uint64_t(64) << 20;
    expectPhrases(errorOf([&] { buildArchive(input, out, o); }),
                  {input + ": 1000000 x 1000000 samples need about ",
                   " to build (streaming: ", "level L-1 in memory, 466 GiB",
                   "but 64.0 MiB are available (memory_limit_bytes)", "raise memory_limit_bytes"});
    // A library's message names its parameters, not a command line's flags.
    EXPECT_EQ(errorOf([&] { buildArchive(input, out, o); }).find("--"), std::string::npos);
    EXPECT_FALSE(fs::exists(out));
    // Whatever this machine has: no machine running the tests has 477 GiB to spare.
    o.memory_limit_bytes = 0;
    expectPhrases(errorOf([&] { buildArchive(input, out, o); }),
                  {input + ": 1000000 x 1000000 samples need about ", "are available ("});
    EXPECT_FALSE(fs::exists(out));
}

TEST(BuildMemory, ALimitBelowTheEstimateRefusesAnOrdinaryBuildAndAboveLetsItThrough)
{
    test::ScratchDir dir;
    const std::string input = test::dataPath("everest_crop.tif");
    BuildOptions o;
    o.memory_limit_bytes = 1 << 20;
    expectPhrases(errorOf([&] { buildArchive(input, dir.path("a.ridge"), o); }),
                  {input + ": 301 x 203 samples need about ", "program and libraries",
                   "1.00 MiB are available"});
    EXPECT_FALSE(fs::exists(dir.path("a.ridge")));
    o.memory_limit_bytes = uint64_t(256) << 20;
    EXPECT_NO_THROW(buildArchive(input, dir.path("a.ridge"), o));
}

TEST(BuildMemory, TheFallbackToInMemoryForVoidsChecksAgain)
{
    // rainier_voids.tif streams until its first void, then needs the whole grid: a limit
    // between the two estimates lets the first check pass and stops the second.
    test::ScratchDir dir;
    const std::string input = test::dataPath("rainier_voids.tif");
    BuildOptions o;
    o.patch_size = 33;
    const io::RasterProbe p = io::probeRaster(input);
    const uint64_t streaming = estimateBuildMemory(p, o, true, false).total();
    const uint64_t in_memory = estimateBuildMemory(p, o, false, true).total();
    ASSERT_LT(streaming, in_memory);
    o.memory_limit_bytes = (streaming + in_memory) / 2;
    expectPhrases(errorOf([&] { buildArchive(input, dir.path("r.ridge"), o); }),
                  {input + ": 257 x 251 samples need about ", "(in memory: ", "void filling"});
    EXPECT_FALSE(fs::exists(dir.path("r.ridge")));
    o.memory_limit_bytes = in_memory;
    EXPECT_NO_THROW(buildArchive(input, dir.path("r.ridge"), o));
}

TEST(BuildOptionsValidation, MaxErrorMustBePositiveWhateverTheCodec)
{
    test::ScratchDir dir;
    const std::string input = test::dataPath("everest_crop.tif");
    BuildOptions o;
    o.codec = "progressive";
    o.max_error = -1.0;
    const std::string message = errorOf([&] { buildArchive(input, dir.path("p.ridge"), o); });
    expectPhrases(message, {"max_error is -1: must be a number in (0, 1e+07]"});
    EXPECT_EQ(message.find("quantization error"), std::string::npos) << message;
    o.max_error = std::nan("");
    expectPhrases(errorOf([&] { buildArchive(input, dir.path("p.ridge"), o); }),
                  {"max_error is nan"});
    o = {};
    o.ingest.z_scale = 1e300;
    expectPhrases(errorOf([&] { buildArchive(input, dir.path("z.ridge"), o); }),
                  {input, "z_scale 1e+300", "heights [-3.2768e+304, 3.2767e+304] m"});
    EXPECT_FALSE(fs::exists(dir.path("z.ridge")));
    o = {};
    o.block_cells = 6;
    expectPhrases(errorOf([&] { buildArchive(input, dir.path("b.ridge"), o); }),
                  {"block_cells is 6"});
}

TEST(PipelineOptionsValidation, HillshadeAndExtractNameTheirBadParameters)
{
    HillshadeOptions h;
    h.azimuth = std::nan("");
    expectPhrases(errorOf([&] { h.validate(); }), {"azimuth (degrees) is nan"});
    h = {};
    h.altitude = 91;
    expectPhrases(errorOf([&] { h.validate(); }),
                  {"altitude (degrees) is 91: must be a number in (0, 90]"});
    h = {};
    h.z_factor = 0;
    expectPhrases(errorOf([&] { h.validate(); }), {"z_factor is 0"});
    h = {};
    h.level = -2;
    expectPhrases(errorOf([&] { writeHillshade("/nonexistent.ridge", "/nonexistent.png", h); }),
                  {"level is -2: must be an integer in [-1, 62]"});
    h = {};
    h.z_factor = INFINITY;
    expectPhrases(errorOf([&] { shadeRelief({0, 0, 0, 0}, 2, 2, 1, 1, h); }), {"z_factor is inf"});

    ExtractOptions e;
    e.window = ExtractWindow{0, 0, 0, 10};
    expectPhrases(errorOf([&] { extractLevel("/nonexistent.ridge", "/nonexistent.tif", e); }),
                  {"window width is 0"});
    e.window = ExtractWindow{-1, 0, 5, 10};
    expectPhrases(errorOf([&] { e.validate(); }), {"window x is -1"});
}
