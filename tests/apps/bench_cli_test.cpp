// `ridge bench` as a user runs it: figures for every frame, a plot, and clear errors.
#include "test_support.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>

using namespace ridge;
namespace fs = std::filesystem;

namespace {

// The Everest fixture at patches of 33 (5 levels) in `dir`.
std::string buildArchive(const test::ScratchDir& dir)
{
    return test::buildEverestWithCli(dir, "everest.ridge", "--patch 33");
}

} // namespace

TEST(BenchCli, FliesEachRendererAlongAPathAndWritesJsonAndAPlot)
{
    test::ScratchDir dir;
    const std::string arc = buildArchive(dir);
    for (const std::string renderer : {"tess", "chunked", "brute"})
        for (const std::string path : {"flyover", "orbit", "teleport"}) {
            const std::string json = dir.path(renderer + path + ".json"),
                              png = dir.path(renderer + path + ".png");
            const test::CommandResult r = test::runRidge(
                "bench '" + arc + "' --lod " + renderer + " --path " + path +
                " --frames 12 --size 160x90 --json-file '" + json + "' --plot '" + png + "'");
            ASSERT_EQ(r.exit_code, 0) << r.output;
            EXPECT_NE(r.output.find("fps min / median / max"), std::string::npos) << r.output;
            std::ifstream in(json);
            const nlohmann::json j = nlohmann::json::parse(in);
            EXPECT_EQ(j["frames"].size(), 12u);
            EXPECT_EQ(j["renderer"], renderer);
            EXPECT_GT(j["summary"]["fps_median"].get<double>(), 0.0);
            for (const auto& f : j["frames"])
                EXPECT_GT(f["triangles"].get<uint64_t>(), 0u) << renderer << " " << path;
            EXPECT_GT(fs::file_size(png), 1000u);
        }
}

TEST(BenchCli, BadInputsGetAClearErrorAndANonZeroExit)
{
    test::ScratchDir dir;
    const std::string arc = buildArchive(dir);
    {
        std::ofstream(dir.path("bad_path.txt")) << "1 2 3 4 5 6\nnot numbers\n";
    }
    struct Case {
        std::string args, phrase;
    };
    for (const Case& c :
         {Case{"--path '" + dir.path("bad_path.txt") + "'", "bad_path.txt:2:"},
          Case{"--path '" + dir.path("missing.txt") + "'", "missing.txt"},
          Case{"--renderer fancy", "--lod fancy: expected tess, chunked, brute"}, Case{"--size 0x0", "--size"},
          Case{"--renderer chunked --chunk-tolerance -1", "--chunk-tolerance"},
          // Unwritable outputs are caught before the run (PLplot would exit() after it).
          Case{"--plot '" + dir.path("no/such/dir/p.png") + "'", "p.png: cannot write"},
          Case{"--json-file '" + dir.path("no/such/dir/f.json") + "'", "f.json: cannot write"}}) {
        const test::CommandResult r = test::runRidge("bench '" + arc + "' --frames 3 " + c.args);
        EXPECT_NE(r.exit_code, 0) << c.args;
        EXPECT_NE(r.output.find(c.phrase), std::string::npos)
            << "expected '" << c.phrase << "' in: " << r.output;
    }
    const test::CommandResult r =
        test::runRidge("bench '" + dir.path("nope.ridge") + "' --frames 3");
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.output.find("nope.ridge"), std::string::npos) << r.output;
}

TEST(BenchCli, TablePrintsTheFractalRingsRowsForEveryRendererWithAndWithoutCulling)
{
    test::ScratchDir dir;
    const std::string arc = buildArchive(dir);
    const test::CommandResult r =
        test::runRidge("bench '" + arc + "' --table --frames 6 --size 160x90");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    for (const char* row :
         {"tess  ", "tess without frustum", "chunked  ", "chunked without frustum", "brute  ",
          "brute without frustum"})
        EXPECT_NE(r.output.find(row), std::string::npos) << row << " in:\n" << r.output;
    EXPECT_NE(r.output.find("cache miss"), std::string::npos);
}

TEST(BenchCli, StreamingFramesAccountForTheirTrafficWithTheGpuOrTheCpuDecoding)
{
    test::ScratchDir dir;
    const std::string arc = test::buildEverestWithCli(
        dir, "everest_progressive.ridge", "--patch 33 --codec progressive --max-error 2");
    for (const std::string decode : {"", " --cpu-decode"}) {
        const std::string json = dir.path("traffic.json");
        const test::CommandResult r =
            test::runRidge("bench '" + arc + "' --path teleport --frames 20 --size 160x90 " +
                           "--upload-mb 0.05 --upload-ms 50 --json-file '" + json + "'" + decode);
        ASSERT_EQ(r.exit_code, 0) << r.output;
        EXPECT_NE(r.output.find("frames over 2x median"), std::string::npos) << r.output;
        std::ifstream in(json);
        const nlohmann::json j = nlohmann::json::parse(in);
        uint64_t read = 0, uploaded = 0;
        int reconstructed = 0;
        for (const auto& f : j["frames"]) {
            read += f["bytes_read"].get<uint64_t>();
            uploaded += f["bytes_uploaded"].get<uint64_t>();
            reconstructed += f["reconstructed"].get<int>();
            // 0.05 MB a frame, but one patch always goes (under 7.4 kB for 33²: 4.4 kB of
            // residuals, or codes and λ).
            EXPECT_LE(f["bytes_uploaded"].get<uint64_t>(), uint64_t(0.05 * 1048576) + 7400);
        }
        EXPECT_GT(read, 0u) << decode;
        EXPECT_GT(uploaded, 0u) << decode;
        EXPECT_EQ(j["summary"]["bytes_read"].get<uint64_t>(), read);
        if (decode.empty())
            EXPECT_GT(reconstructed, 0) << "progressive patches reconstructed on the GPU";
        else
            EXPECT_EQ(reconstructed, 0);
        EXPECT_EQ(j["gpu_reconstruction"].get<bool>(), decode.empty());
    }
}

// --bytes-per-view: selection only, no GL; every frame's cold-cache bytes, the progressive
// archive's ancestors counted, the lossless one's not.
TEST(BenchCli, BytesPerViewReportsEveryFramesColdCacheBytesWithoutRendering)
{
    test::ScratchDir dir;
    const std::string progressive = test::buildEverestWithCli(
        dir, "progressive.ridge", "--patch 33 --codec progressive --max-error 2");
    const std::string lossless = buildArchive(dir);
    for (const std::string& arc : {progressive, lossless}) {
        const bool is_progressive = arc == progressive;
        const test::CommandResult r = test::runRidgeStdout(
            "bench '" + arc + "' --bytes-per-view --path orbit --frames 9 --json");
        ASSERT_EQ(r.exit_code, 0) << r.output;
        const nlohmann::json j = nlohmann::json::parse(r.output);
        ASSERT_EQ(j["frames"].size(), 9u);
        EXPECT_EQ(j["counts_ancestors"].get<bool>(), is_progressive);
        uint64_t largest = 0;
        for (const auto& f : j["frames"]) {
            const uint64_t bytes = f["bytes"], patches = f["patches"], selected = f["selected"];
            EXPECT_GT(bytes, 0u);
            if (is_progressive) {
                EXPECT_GT(patches, selected) << "ancestors are fetched too";
            } else {
                EXPECT_EQ(patches, selected);
            }
            largest = std::max(largest, bytes);
        }
        const auto& s = j["summary"];
        EXPECT_EQ(s["bytes_max"].get<uint64_t>(), largest);
        EXPECT_EQ(s["near_bytes"], j["frames"][0]["bytes"]);
        EXPECT_EQ(s["far_bytes"], j["frames"][8]["bytes"]);
        EXPECT_GE(s["path_bytes"].get<uint64_t>(), largest);
        EXPECT_LE(s["path_bytes"].get<uint64_t>(), j["archive_blob_bytes"].get<uint64_t>());
    }
}
