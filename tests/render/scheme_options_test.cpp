// LOD schemes' own options (ridge/render/scheme_options.h): the KEY=VALUE parser against a
// made-up scheme's descriptors, then every registered scheme's, without a GL context.
#include "error_expectations.h"
#include "scheme_option_cases.h"

#include "ridge/render/scheme_options.h"
#include "ridge/render/terrain_renderer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>

using namespace ridge;
using render::SchemeOption;
using render::SchemeOptions;
using test::expectError;

namespace {

// One option of every kind.
const std::vector<SchemeOption>& demoOptions()
{
    static const std::vector<SchemeOption> options = {
        SchemeOption::number("tolerance", "how far", ValueRange::closed(0.0, 100.0), 0.5),
        SchemeOption::integer("count", "how many", 1, 16, 4),
        SchemeOption::choice("layout", "which", {"standard", "float", "compact"}, "compact"),
        SchemeOption::flag("meshes", "whether", true),
    };
    return options;
}

SchemeOptions demo(std::string_view pairs, std::string_view what = "LOD scheme")
{
    return render::parseSchemeOptions("demo", demoOptions(), pairs, what);
}

} // namespace

TEST(SchemeOptions, OptionsNotGivenTakeTheirDefaults)
{
    const SchemeOptions o = demo("");
    EXPECT_EQ(o.scheme(), "demo");
    EXPECT_EQ(o.number("tolerance"), 0.5);
    EXPECT_EQ(o.integer("count"), 4);
    EXPECT_EQ(o.choice("layout"), "compact");
    EXPECT_TRUE(o.flag("meshes"));
    EXPECT_EQ(o.spec(), "demo,tolerance=0.5,count=4,layout=compact,meshes=on");
}

TEST(SchemeOptions, GivenOptionsInAnyOrder)
{
    const SchemeOptions o = demo("meshes=off,layout=float,count=16,tolerance=100");
    EXPECT_EQ(o.number("tolerance"), 100.0);
    EXPECT_EQ(o.integer("count"), 16);
    EXPECT_EQ(o.choice("layout"), "float");
    EXPECT_FALSE(o.flag("meshes"));
    EXPECT_EQ(o.spec(), "demo,tolerance=100,count=16,layout=float,meshes=off");
    // The spec spells every option in declaration order, and parses back to itself.
    EXPECT_EQ(demo(o.spec().substr(5)).spec(), o.spec());
    // Numbers as the command line spells them: sign, point, exponent; the ends of the range.
    EXPECT_EQ(demo("tolerance=+1e1").number("tolerance"), 10.0);
    EXPECT_EQ(demo("tolerance=.25").number("tolerance"), 0.25);
    EXPECT_EQ(demo("tolerance=0").number("tolerance"), 0.0);
    EXPECT_EQ(demo("tolerance=-0").number("tolerance"), 0.0);
    EXPECT_EQ(demo("count=+1").integer("count"), 1);
    EXPECT_EQ(demo("tolerance=1e-999").number("tolerance"), 0.0); // underflows to 0, in range
}

TEST(SchemeOptions, ValuesOutsideTheirOptionAreRefusedNamingTheOption)
{
    expectError([] { demo("tolerance=nan"); },
                "LOD scheme demo: tolerance=nan: must be a number in [0, 100]");
    expectError([] { demo("tolerance=-1", "--lod"); },
                "--lod demo: tolerance=-1: must be a number in [0, 100]");
    expectError([] { demo("tolerance=inf"); }, "tolerance=inf: must be");
    expectError([] { demo("tolerance=-Infinity"); }, "tolerance=-Infinity: must be");
    expectError([] { demo("tolerance=1e999"); }, "tolerance=1e999: must be a number in [0, 100]");
    expectError([] { demo("tolerance=100.5"); }, "tolerance=100.5: must be");
    expectError([] { demo("tolerance=0x10"); }, "tolerance=0x10: must be");
    expectError([] { demo("tolerance= 1"); }, "tolerance= 1: must be");
    expectError([] { demo("tolerance=1e"); }, "tolerance=1e: must be");
    expectError([] { demo("tolerance=--1"); }, "tolerance=--1: must be");
    expectError([] { demo("count=0"); }, "count=0: must be an integer in [1, 16]");
    expectError([] { demo("count=17"); }, "count=17: must be an integer in [1, 16]");
    expectError([] { demo("count=1.5"); }, "count=1.5: must be an integer in [1, 16]");
    expectError([] { demo("count=-1"); }, "count=-1: must be");
    expectError([] { demo("count=99999999999999999999"); }, "count=99999999999999999999: must be");
    expectError([] { demo("layout=fancy"); },
                "layout=fancy: must be one of standard, float, compact");
    expectError([] { demo("layout=Compact"); }, "layout=Compact: must be one of");
    expectError([] { demo("meshes=yes"); }, "meshes=yes: must be on or off");
    expectError([] { demo("meshes=ON"); }, "meshes=ON: must be on or off");
    // The values the command-line tests try on every registered option.
    for (const SchemeOption& o : demoOptions())
        for (const std::string& v : test::refusedValues(o))
            expectError([&] { demo(o.key + "=" + v); }, "demo: " + o.key + "=" + v + ": must be ");
}

TEST(SchemeOptions, UnknownDuplicatedAndMalformedPairsAreRefused)
{
    expectError(
        [] { demo("colour=red"); },
        "LOD scheme demo: no option 'colour' (demo takes tolerance, count, layout, meshes)");
    expectError([] { demo("count=2,count=3"); }, "demo: count given twice");
    expectError([] { demo("count=2,meshes=on,count=2"); }, "count given twice");
    expectError([] { demo("count"); }, "demo: 'count' is not KEY=VALUE");
    expectError([] { demo("=3"); }, "'=3' is not KEY=VALUE");
    expectError([] { demo("count="); }, "'count=' is not KEY=VALUE");
    expectError([] { demo(",count=2"); }, "demo: an empty option");
    expectError([] { demo("count=2,"); }, "an empty option");
    expectError([] { demo("count=2,,meshes=on"); }, "an empty option");
    expectError([] { demo("count=2=3"); }, "count=2=3: must be an integer");
    expectError([] { demo("Rings=2"); }, "no option 'Rings'");
    expectError([] { render::parseSchemeOptions("plain", {}, "x=1"); },
                "LOD scheme plain: no option 'x' (plain takes no options)");
}

TEST(SchemeOptions, ReadingAnOptionAsAnotherKindIsAnError)
{
    const SchemeOptions o = demo("");
    expectError([&] { o.number("count"); }, "LOD scheme demo declares no number option 'count'");
    expectError([&] { o.flag("nothing"); }, "declares no on/off option 'nothing'");
    expectError([] { SchemeOptions().choice("layout"); }, "declares no choice option 'layout'");
}

TEST(SchemeOptions, DescriptorsSayWhatTheyTake)
{
    const std::vector<SchemeOption>& d = demoOptions();
    EXPECT_EQ(d[0].describe(), "a number in [0, 100]");
    EXPECT_EQ(d[1].describe(), "an integer in [1, 16]");
    EXPECT_EQ(d[2].describe(), "one of standard, float, compact");
    EXPECT_EQ(d[3].describe(), "on or off");
    EXPECT_EQ(d[2].placeholder(), "standard|float|compact");
    EXPECT_EQ(d[3].placeholder(), "on|off");
    EXPECT_EQ(d[0].default_value, "0.5");
    EXPECT_EQ(d[3].default_value, "on");
}

// ---- The registered schemes ------------------------------------------------------------------

TEST(SchemeOptions, EveryRegisteredSchemeParsesWithItsDefaultsAndRoundTrips)
{
    const std::vector<std::string> names = render::lodSchemeNames();
    ASSERT_FALSE(names.empty());
    EXPECT_EQ(render::defaultLodScheme(), names.front());
    EXPECT_EQ(render::RenderSettings{}.scheme, names.front());
    for (const std::string& name : names) {
        const SchemeOptions o = render::parseSchemeSpec(name);
        EXPECT_EQ(o.scheme(), name);
        EXPECT_EQ(render::parseSchemeSpec(o.spec()).spec(), o.spec()) << name;
        std::set<std::string> keys;
        for (const SchemeOption& option : render::lodSchemeOptions(name)) {
            EXPECT_TRUE(keys.insert(option.key).second) << name << ": " << option.key << " twice";
            EXPECT_FALSE(option.help.empty()) << name << ": " << option.key;
            EXPECT_EQ(option.key.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789-"),
                      std::string::npos)
                << name << ": " << option.key;
            EXPECT_NE(o.spec().find("," + option.key + "=" + option.default_value),
                      std::string::npos)
                << o.spec();
        }
    }
}

TEST(SchemeOptions, EveryRegisteredOptionRefusesBadValuesNamingTheSchemeAndTheOption)
{
    for (const std::string& name : render::lodSchemeNames()) {
        std::string keys;
        for (const SchemeOption& o : render::lodSchemeOptions(name)) {
            keys += (keys.empty() ? "" : ", ") + o.key;
            for (const std::string& v : test::refusedValues(o))
                expectError([&] { render::parseSchemeSpec(name + "," + o.key + "=" + v, "--lod"); },
                            "--lod " + name + ": " + o.key + "=" + v + ": must be " + o.describe());
            expectError(
                [&] {
                    render::parseSchemeSpec(name + "," + o.key + "=" + o.default_value + "," +
                                            o.key + "=" + o.default_value);
                },
                name + ": " + o.key + " given twice");
        }
        expectError([&] { render::parseSchemeSpec(name + ",no-such-key=1"); },
                    "LOD scheme " + name + ": no option 'no-such-key' (" + name +
                        (keys.empty() ? " takes no options)" : " takes " + keys + ")"));
        expectError([&] { render::parseSchemeSpec(name + ","); }, name + ": an empty option");
        expectError([&] { render::parseSchemeSpec(name + ",x"); }, "'x' is not KEY=VALUE");
    }
    expectError([] { render::parseSchemeSpec("no-such-scheme,x=1", "--lod"); },
                "--lod no-such-scheme: not a LOD scheme; expected one of " +
                    render::lodSchemeList());
    expectError([] { render::parseSchemeSpec(""); }, "LOD scheme '': not a LOD scheme");
    expectError([] { render::parseSchemeSpec(" " + render::defaultLodScheme()); },
                "not a LOD scheme");
    expectError([] { render::lodSchemeOptions("no-such-scheme"); }, "unknown LOD scheme");
}

TEST(SchemeOptions, VariantsCoverEveryChoiceAndFlagOfEveryScheme)
{
    const std::vector<std::string> variants = render::lodSchemeVariants();
    for (const std::string& name : render::lodSchemeNames()) {
        EXPECT_NE(std::find(variants.begin(), variants.end(), name), variants.end()) << name;
        for (const SchemeOption& o : render::lodSchemeOptions(name)) {
            std::vector<std::string> values = o.choices;
            if (o.kind == SchemeOption::Kind::Flag)
                values = {"on", "off"};
            for (const std::string& v : values) {
                const std::string spec = v == o.default_value ? name : name + "," + o.key + "=" + v;
                EXPECT_NE(std::find(variants.begin(), variants.end(), spec), variants.end())
                    << spec;
            }
        }
    }
    for (const std::string& spec : variants)
        EXPECT_NO_THROW(render::parseSchemeSpec(spec)) << spec;
}

TEST(SchemeOptions, RendererOptionsTakeSpecsOnePerScheme)
{
    render::RendererOptions o;
    o.schemes = render::lodSchemeVariants();
    o.schemes.resize(1);
    EXPECT_NO_THROW(o.validate());
    o.schemes = render::lodSchemeNames();
    EXPECT_NO_THROW(o.validate());
    const std::string first = render::defaultLodScheme();
    o.schemes = {first, first};
    expectError([&] { o.validate(); }, "LOD scheme " + first + " is given twice");
    o.schemes = {first + ",no-such-key=1"};
    expectError([&] { o.validate(); }, "LOD scheme " + first + ": no option 'no-such-key'");
    o.schemes = {"no-such-scheme"};
    expectError([&] { o.validate(); }, "no-such-scheme: not a LOD scheme");
    // A scheme's name alone is what RenderSettings::scheme takes; a spec is not a name.
    render::RenderSettings s;
    s.scheme = first + ",x=1";
    expectError([&] { s.validate(); }, "unknown LOD scheme");
}
