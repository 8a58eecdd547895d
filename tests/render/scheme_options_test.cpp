// LOD schemes' own options (ridge/render/scheme_options.h): the KEY=VALUE parser against a
// made-up scheme's descriptors, without a GL context.
#include "error_expectations.h"
#include "scheme_option_cases.h"

#include "ridge/render/scheme_options.h"

#include <gtest/gtest.h>

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
        SchemeOption::integer("rings", "how many", 1, 16, 4),
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
    EXPECT_EQ(o.integer("rings"), 4);
    EXPECT_EQ(o.choice("layout"), "compact");
    EXPECT_TRUE(o.flag("meshes"));
    EXPECT_EQ(o.spec(), "demo,tolerance=0.5,rings=4,layout=compact,meshes=on");
}

TEST(SchemeOptions, GivenOptionsInAnyOrder)
{
    const SchemeOptions o = demo("meshes=off,layout=float,rings=16,tolerance=100");
    EXPECT_EQ(o.number("tolerance"), 100.0);
    EXPECT_EQ(o.integer("rings"), 16);
    EXPECT_EQ(o.choice("layout"), "float");
    EXPECT_FALSE(o.flag("meshes"));
    EXPECT_EQ(o.spec(), "demo,tolerance=100,rings=16,layout=float,meshes=off");
    // The spec spells every option in declaration order, and parses back to itself.
    EXPECT_EQ(demo(o.spec().substr(5)).spec(), o.spec());
    // Numbers as the command line spells them: sign, point, exponent; the ends of the range.
    EXPECT_EQ(demo("tolerance=+1e1").number("tolerance"), 10.0);
    EXPECT_EQ(demo("tolerance=.25").number("tolerance"), 0.25);
    EXPECT_EQ(demo("tolerance=0").number("tolerance"), 0.0);
    EXPECT_EQ(demo("tolerance=-0").number("tolerance"), 0.0);
    EXPECT_EQ(demo("rings=+1").integer("rings"), 1);
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
    expectError([] { demo("rings=0"); }, "rings=0: must be an integer in [1, 16]");
    expectError([] { demo("rings=17"); }, "rings=17: must be an integer in [1, 16]");
    expectError([] { demo("rings=1.5"); }, "rings=1.5: must be an integer in [1, 16]");
    expectError([] { demo("rings=-1"); }, "rings=-1: must be");
    expectError([] { demo("rings=99999999999999999999"); }, "rings=99999999999999999999: must be");
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
        "LOD scheme demo: no option 'colour' (demo takes tolerance, rings, layout, meshes)");
    expectError([] { demo("rings=2,rings=3"); }, "demo: rings given twice");
    expectError([] { demo("rings=2,meshes=on,rings=2"); }, "rings given twice");
    expectError([] { demo("rings"); }, "demo: 'rings' is not KEY=VALUE");
    expectError([] { demo("=3"); }, "'=3' is not KEY=VALUE");
    expectError([] { demo("rings="); }, "'rings=' is not KEY=VALUE");
    expectError([] { demo(",rings=2"); }, "demo: an empty option");
    expectError([] { demo("rings=2,"); }, "an empty option");
    expectError([] { demo("rings=2,,meshes=on"); }, "an empty option");
    expectError([] { demo("rings=2=3"); }, "rings=2=3: must be an integer");
    expectError([] { demo("Rings=2"); }, "no option 'Rings'");
    expectError([] { render::parseSchemeOptions("plain", {}, "x=1"); },
                "LOD scheme plain: no option 'x' (plain takes no options)");
}

TEST(SchemeOptions, ReadingAnOptionAsAnotherKindIsAnError)
{
    const SchemeOptions o = demo("");
    expectError([&] { o.number("rings"); }, "LOD scheme demo declares no number option 'rings'");
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
