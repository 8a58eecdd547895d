// --lod NAME[,KEY=VALUE...] as render, bench and view take it: every registered scheme's own
// options, listed by --help from the descriptors its module declares, refused with the usage
// status 2 and a message naming the scheme and the option when a value is outside them, and
// taken when they are inside. The schemes and options come from the registry, so a new scheme
// is covered without a change here.
#include "scheme_option_cases.h"
#include "test_support.h"

#include "ridge/render/scheme_options.h"
#include "ridge/render/terrain_renderer.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>

using namespace ridge;
using render::SchemeOption;

namespace {

// 'text', for a command line (specs and paths hold no quote).
std::string inShell(const std::string& text)
{
    return "'" + text + "'";
}

class LodSpecCli : public ::testing::Test {
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

    // `ridge COMMAND` with `spec` must exit 2 naming every phrase, and write nothing.
    static void expectRefused(const std::string& command, const std::string& spec,
                              const std::vector<std::string>& phrases)
    {
        const test::CommandResult r = test::runRidge(command + " --lod " + inShell(spec));
        SCOPED_TRACE(command + " --lod " + spec);
        EXPECT_EQ(r.exit_code, 2) << r.output;
        for (const std::string& p : phrases)
            EXPECT_NE(r.output.find(p), std::string::npos)
                << "expected '" << p << "' in: " << r.output;
        EXPECT_EQ(r.output.find("internal error"), std::string::npos) << r.output;
        EXPECT_FALSE(std::filesystem::exists(scratch_->path("out.png")));
    }

    static std::string render()
    {
        return "render " + inShell(*archive_) + " -o " + out() + " --size 64x48";
    }
    static std::string bench()
    {
        return "bench " + inShell(*archive_) + " --frames 2 --size 64x48";
    }
    static std::string out() { return inShell(scratch_->path("out.png")); }

    inline static test::ScratchDir* scratch_ = nullptr;
    inline static std::string* archive_ = nullptr;
};

} // namespace

TEST_F(LodSpecCli, HelpListsEverySchemeWithItsOptionsFromTheirDescriptors)
{
    for (const std::string command : {"render", "bench", "view"}) {
        const test::CommandResult r = test::runRidge(command + " --help");
        ASSERT_EQ(r.exit_code, 0) << r.output;
        SCOPED_TRACE(command + " --help");
        EXPECT_NE(r.output.find("NAME[,KEY=VALUE...]"), std::string::npos) << r.output;
        for (const std::string& name : render::lodSchemeNames()) {
            EXPECT_NE(r.output.find(name + ": " + render::lodSchemeDescription(name)),
                      std::string::npos)
                << name << " in:\n"
                << r.output;
            for (const SchemeOption& o : render::lodSchemeOptions(name)) {
                const std::string usage = o.key + "=" + o.placeholder() + " (";
                const size_t at = r.output.find(usage, r.output.find(name + ": "));
                ASSERT_NE(at, std::string::npos) << usage << " in:\n" << r.output;
                const std::string line = r.output.substr(at, r.output.find('\n', at) - at);
                EXPECT_NE(line.find("default " + o.default_value), std::string::npos) << line;
                if (o.kind == SchemeOption::Kind::Number || o.kind == SchemeOption::Kind::Integer) {
                    EXPECT_NE(line.find(o.describe()), std::string::npos) << line;
                }
            }
        }
    }
    // The per-scheme flags of earlier releases are gone: their options are the spec's.
    for (const std::string old : {"--chunk-tolerance", "--grid-chunks", "--geomorph-layout",
                                  "--geomorph-normals", "--geomorph-per-frame"})
        for (const std::string command : {"bench", "view"})
            EXPECT_EQ(test::runRidge(command + " --help").output.find(old), std::string::npos)
                << old;
}

TEST_F(LodSpecCli, EveryOptionOfEverySchemeRefusesBadValuesWithTheUsageStatus)
{
    for (const std::string& name : render::lodSchemeNames())
        for (const SchemeOption& o : render::lodSchemeOptions(name))
            for (const std::string& v : test::refusedValues(o))
                expectRefused(
                    render(), name + "," + o.key + "=" + v,
                    {"--lod " + name + ": " + o.key + "=" + v + ": must be " + o.describe()});
}

TEST_F(LodSpecCli, UnknownSchemesKeysDuplicatesAndMalformedPairsAreRefused)
{
    const std::string first = render::defaultLodScheme();
    std::string keys;
    for (const SchemeOption& o : render::lodSchemeOptions(first))
        keys += (keys.empty() ? "" : ", ") + o.key;
    const std::string takes = keys.empty() ? " takes no options" : " takes " + keys;
    for (const std::string& command : {render(), bench()}) {
        expectRefused(
            command, "fancy",
            {"--lod fancy: not a LOD scheme; expected one of " + render::lodSchemeList()});
        expectRefused(command, first + ",no-such-key=1",
                      {"--lod " + first + ": no option 'no-such-key' (" + first + takes + ")"});
        expectRefused(command, first + ",", {"--lod " + first + ": an empty option"});
        expectRefused(command, first + ",key", {"--lod " + first + ": 'key' is not KEY=VALUE"});
    }
    // The hidden --renderer of bench checks the same.
    const test::CommandResult r = test::runRidge(bench() + " --renderer fancy");
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("--lod fancy: not a LOD scheme"), std::string::npos) << r.output;
    // A key given twice, for every scheme that takes one.
    for (const std::string& name : render::lodSchemeNames())
        for (const SchemeOption& o : render::lodSchemeOptions(name)) {
            const std::string pair = "," + o.key + "=" + o.default_value;
            expectRefused(bench(), name + pair + pair,
                          {"--lod " + name + ": " + o.key + " given twice"});
        }
    // view refuses before it looks for a display; and a scheme given twice.
    const std::string view = "view " + inShell(*archive_) + " --frames 1";
    expectRefused(view, first + ",no-such-key=1", {"no option 'no-such-key'"});
    const test::CommandResult twice = test::runRidge(view + " --lod " + first + " --lod " + first);
    EXPECT_EQ(twice.exit_code, 2) << twice.output;
    EXPECT_NE(twice.output.find("LOD scheme " + first + " is given twice"), std::string::npos)
        << twice.output;
}

TEST_F(LodSpecCli, EveryVariantOfEverySchemeRendersAndBenchReportsItsSpec)
{
    // Each scheme, and each value of its choices and flags: the option reaches the renderer.
    for (const std::string& spec : render::lodSchemeVariants()) {
        const std::string png = scratch_->path("variant.png");
        const test::CommandResult r =
            test::runRidgeStdout("render " + inShell(*archive_) + " -o " + inShell(png) +
                                 " --size 64x48 --samples 1 " + "--json --lod " + inShell(spec));
        ASSERT_EQ(r.exit_code, 0) << spec << ": " << r.output;
        const nlohmann::json j = nlohmann::json::parse(r.output);
        EXPECT_GT(j.at("triangles").get<uint64_t>(), 0u) << spec;
        std::filesystem::remove(png);
    }
    // bench's JSON: the scheme's name, and its whole spec with every option's value.
    const render::SchemeOptions last = render::parseSchemeSpec(render::lodSchemeVariants().back());
    const test::CommandResult r = test::runRidgeStdout(bench() + " --json --lod " +
                                                       inShell(render::lodSchemeVariants().back()));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const nlohmann::json j = nlohmann::json::parse(r.output);
    EXPECT_EQ(j.at("renderer"), last.scheme());
    EXPECT_EQ(j.at("scheme_spec"), last.spec());
}
