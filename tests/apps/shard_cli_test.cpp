// `ridge plan`, `ridge build --plan` and `ridge merge` as a driver runs them: one JSON line a
// step, the archive of `ridge build`, and bad options and inputs refused with the usage
// status or a message naming the file or shard.
#include "test_support.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>

namespace {

using ridge::test::runRidge;
using ridge::test::runRidgeStdout;

nlohmann::json step(const std::string& args)
{
    const auto r = runRidgeStdout(args + " --json");
    EXPECT_EQ(r.exit_code, 0) << args << ": " << r.output;
    EXPECT_EQ(r.output.find('\n'), r.output.size() - 1) << "one JSON line: " << r.output;
    return nlohmann::json::parse(r.output);
}

TEST(ShardCli, PlanStepsAndMergeMakeRidgeBuildsArchive)
{
    const ridge::test::ScratchDir dir;
    const std::string source = ridge::test::dataPath("everest_crop.tif");
    const std::string plan = dir.path("plan.json");
    const nlohmann::json planned =
        step("plan " + source + " --shard-level 2 --patch 33 -o " + plan + " -q");
    ASSERT_EQ(planned["shards"].size(), 6u); // level 2 of 5: 3 x 2 patches
    std::string summaries, segments;
    for (int id = 0; id < 6; ++id) {
        const std::string s = dir.path("s" + std::to_string(id));
        const nlohmann::json r =
            step("build --plan " + plan + " --shard " + std::to_string(id) + " --summary -o " + s);
        EXPECT_EQ(r["step"], "summary");
        EXPECT_EQ(r["shard"], id);
        EXPECT_GT(r["peak_rss_bytes"].get<uint64_t>(), 0u);
        summaries += " " + s;
    }
    const std::string top = dir.path("top");
    const nlohmann::json c =
        step("build --plan " + plan + " --coordinate --summaries" + summaries + " -o " + top);
    EXPECT_EQ(c["pending_stage"], 0); // lossless: nothing to learn
    for (int id = 0; id < 6; ++id) {
        const std::string g = dir.path("g" + std::to_string(id));
        step("build --plan " + plan + " --shard " + std::to_string(id) + " --top " + top + " -o " +
             g);
        const nlohmann::json again =
            step("build --plan " + plan + " --shard " + std::to_string(id) + " --top " + top +
                 " -o " + g + " --skip-unchanged");
        EXPECT_TRUE(again["skipped"].get<bool>());
        segments += " " + g;
    }
    const nlohmann::json merged =
        step("merge " + plan + " " + top + segments + " -o " + dir.path("sharded.ridge"));
    EXPECT_EQ(merged["patches"], 99); // 70 + 20 + 6 + 2 + 1
    const auto single =
        runRidge("build " + source + " --patch 33 -o " + dir.path("single.ridge") + " -q");
    ASSERT_EQ(single.exit_code, 0) << single.output;
    EXPECT_EQ(ridge::test::readFile(dir.path("sharded.ridge")),
              ridge::test::readFile(dir.path("single.ridge")));
}

TEST(ShardCli, BadOptionsAndInputsAreRefused)
{
    const ridge::test::ScratchDir dir;
    const std::string source = ridge::test::dataPath("everest_crop.tif");
    const std::string plan = dir.path("plan.json");
    for (const std::string& args :
         {"plan " + source + " --shard-level -1 -o " + plan,
          "plan " + source + " -o " + plan,                // --shard-level is required
          "plan --shard-level 1 -o " + plan,               // no input
          "build --plan " + plan + " -o " + dir.path("x"), // no step
          "build " + source + " --plan " + plan + " --shard 0 --summary -o " + dir.path("x"),
          "build --plan " + plan + " --coordinate --shard 0 --summaries a -o " + dir.path("x"),
          "build --plan " + plan + " --shard -3 --summary -o " + dir.path("x")}) {
        const auto r = runRidge(args);
        EXPECT_EQ(r.exit_code, 2) << args << ": " << r.output;
    }
    EXPECT_FALSE(std::filesystem::exists(plan));
    const auto deep = runRidge("plan " + source + " --shard-level 7 --patch 33 -o " + plan);
    EXPECT_EQ(deep.exit_code, 1);
    EXPECT_NE(deep.output.find("--shard-level 7: must be 0..4"), std::string::npos) << deep.output;
    // A non-integer source is planned too: its code mapping is settled by the plan.
    std::ofstream(dir.path("float.asc")) << "ncols 3\nnrows 3\nxllcorner 0\nyllcorner 0\n"
                                            "cellsize 1\n1.5 2.5 3.5\n1 2 3\n4 5 6\n";
    const auto floats = runRidge("plan " + dir.path("float.asc") + " --shard-level 0 -q -o " +
                                 dir.path("float.json"));
    EXPECT_EQ(floats.exit_code, 0) << floats.output;
    EXPECT_NE(ridge::test::readFile(dir.path("float.json")).find("\"code_mapping\": {"),
              std::string::npos);
    const auto absent = runRidge("build --plan " + dir.path("absent.json") +
                                 " --shard 0 --summary -o " + dir.path("x"));
    EXPECT_EQ(absent.exit_code, 1);
    EXPECT_NE(absent.output.find("absent.json: cannot open"), std::string::npos) << absent.output;
    ASSERT_EQ(
        runRidge("plan " + source + " --shard-level 2 --patch 33 -o " + plan + " -q").exit_code, 0);
    const auto shard =
        runRidge("build --plan " + plan + " --shard 9 --summary -o " + dir.path("x"));
    EXPECT_EQ(shard.exit_code, 1);
    EXPECT_NE(shard.output.find("no shard 9 (0..5)"), std::string::npos) << shard.output;
    const auto over = runRidge("build --plan " + plan + " --shard 0 --summary -o " + plan);
    EXPECT_EQ(over.exit_code, 1);
    EXPECT_NE(over.output.find("same file as the input"), std::string::npos) << over.output;
    EXPECT_FALSE(std::filesystem::exists(dir.path("x")));
}

} // namespace
