// Every registered codec, end to end on a real DEM (tests/data/everest_crop.tif), through the
// registry's names only: it builds, its archive reopens with the codec its header names, every
// level decodes within the codec's bound, and `verify --source` holds it to that bound. A codec
// added by its module and one registration line is held to this without naming it here.
#include "test_support.h"

#include "ridge/archive/archive_reader.h"
#include "ridge/codec/codec_registry.h"
#include "ridge/core/error.h"
#include "ridge/io/raster_source.h"
#include "ridge/pipeline/build.h"
#include "ridge/pipeline/level_decoder.h"
#include "ridge/pipeline/verify.h"

#include <gtest/gtest.h>

#include <set>

using namespace ridge;

namespace {

std::vector<std::string> registeredNames()
{
    std::vector<std::string> names;
    for (const CodecInfo& c : codecRegistry())
        names.push_back(c.name);
    return names;
}

class EveryRegisteredCodec : public ::testing::TestWithParam<std::string> {};

} // namespace

TEST(CodecRegistry, IdsNamesAndAliasesAreUniqueAndEveryHookIsThere)
{
    std::set<uint32_t> ids;
    std::set<std::string> names;
    for (const CodecInfo& c : codecRegistry()) {
        EXPECT_TRUE(ids.insert(uint32_t(c.id)).second) << c.name << ": id used twice";
        EXPECT_TRUE(names.insert(c.name).second) << c.name;
        for (const char* alias : c.aliases)
            EXPECT_TRUE(names.insert(alias).second) << alias;
        EXPECT_TRUE(c.spec_problem && c.from_spec && c.from_settings) << c.name;
        EXPECT_EQ(codecSpecProblem(c.name), "") << c.name;
        EXPECT_EQ(findCodec(c.name), &c);
        EXPECT_NE(codecUsage().find(std::string(c.name) + ": "), std::string::npos);
    }
    // Unknown names and ids are refused with the names and ids there are.
    EXPECT_NE(codecSpecProblem("jpeg2001").find(codecNameList()), std::string::npos);
    std::string problem;
    EXPECT_EQ(makeCodec(CodecId{77}, {}, &problem), nullptr);
    EXPECT_EQ(problem.rfind("codec_id is 77: must be ", 0), 0u) << problem;
    for (const CodecInfo& c : codecRegistry())
        EXPECT_NE(problem.find(std::to_string(uint32_t(c.id)) + " (" + c.name + ")"),
                  std::string::npos)
            << problem;
    // A codec's options belong to it: another codec's option is refused, naming the codec.
    for (const CodecInfo& c : codecRegistry()) {
        const std::string bad = std::string(c.name) + ",no-such-option=1";
        EXPECT_NE(codecSpecProblem(bad).find(c.name), std::string::npos) << bad;
        EXPECT_FALSE(codecIdOf(bad)) << bad;
        EXPECT_THROW(makeCodec(bad, 1.0, 4), Error) << bad;
    }
}

TEST_P(EveryRegisteredCodec, BuildsReopensAndHoldsItsBoundOnARealDem)
{
    const CodecInfo& info = *findCodec(GetParam());
    test::ScratchDir dir;
    const std::string source = test::dataPath("everest_crop.tif");
    const std::string out = dir.path("everest.ridge");
    BuildOptions options;
    options.patch_size = 33;
    options.codec = info.name;
    if (info.lossy)
        options.max_error = 4.0; // metres
    buildArchive(source, out, options);

    const archive::ArchiveReader reader(out);
    EXPECT_EQ(reader.codec().id(), info.id);
    EXPECT_EQ(std::string(reader.codec().name()), info.name);
    EXPECT_EQ(reader.codec().lossless(), !info.lossy);

    // The finest level against the source's codes, within the codec's own bound δ_l.
    const io::ElevationRaster raster = io::ingestRaster(source);
    const int finest = reader.geometry().finestLevel();
    const CodeGrid decoded = decodeLevel(reader, finest);
    ASSERT_EQ(decoded.codes.size(), raster.grid.codes.size());
    const double bound = reader.codec().levelErrorBound(finest);
    double worst = 0.0;
    for (size_t i = 0; i < decoded.codes.size(); ++i)
        worst = std::max(worst, std::abs(double(decoded.codes[i]) - raster.grid.codes[i]));
    EXPECT_LE(worst, bound) << info.name;
    if (!info.lossy) {
        EXPECT_EQ(decoded.codes, raster.grid.codes) << info.name;
    }

    VerifyOptions v;
    v.source = source;
    const VerifyReport report = verifyArchive(out, v);
    EXPECT_TRUE(report.ok()) << info.name << ": " << report.problems.front();
    std::printf("[%s] finest level within %.0f of %.0f codes allowed\n", info.name, worst, bound);
}

INSTANTIATE_TEST_SUITE_P(Registry, EveryRegisteredCodec, ::testing::ValuesIn(registeredNames()),
                         [](const auto& p) { return p.param; });
