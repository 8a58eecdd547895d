// `ridge bench` as a user runs it: figures for every frame, a plot, and clear errors.
#include "test_support.h"

#include "ridge/codec/codec_registry.h"
#include "ridge/codec/height_codec.h"
#include "ridge/render/terrain_renderer.h"

#include <gtest/gtest.h>

#include <map>
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
    for (const std::string& renderer : render::lodSchemeNames())
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
          Case{"--renderer fancy",
               "--lod fancy: not a LOD scheme; expected one of " + render::lodSchemeList()},
          Case{"--size 0x0", "--size"}, Case{"--refine-steps -1", "--refine-steps"},
          Case{"--refine-steps 1e9", "--refine-steps"},
          Case{"--refine-steps nan", "--refine-steps"},
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
    for (const std::string& scheme : render::lodSchemeNames())
        for (const std::string& row : {scheme + "  ", scheme + " without frustum"})
            EXPECT_NE(r.output.find(row), std::string::npos) << row << " in:\n" << r.output;
    EXPECT_NE(r.output.find("cache miss"), std::string::npos);
}

TEST(BenchCli, TableAddsTheBaseIncrementalRowsForAnArchiveThatRefinesInPlace)
{
    // The fractal-rings paper's last row: streamed, decoded on the GPU, far patches with fewer
    // iterations refined as they near; schemes that need codes on the CPU say why they have no
    // such row. Every registered codec that refines in place gets it.
    test::ScratchDir dir;
    size_t tested = 0;
    for (const ridge::CodecInfo& c : codecRegistry()) {
        if (!c.lossy || !makeCodec(c.name, 1.0, 5)->capabilities().gpu.refinable)
            continue;
        ++tested;
        const std::string arc = test::buildEverestWithCli(dir, std::string(c.name) + ".ridge",
                                                          std::string("--patch 33 --codec ") +
                                                              c.name + " --max-error 4");
        const test::CommandResult r =
            test::runRidge("bench '" + arc + "' --table --frames 8 --size 160x90 --json-file '" +
                           dir.path(std::string(c.name) + ".json") + "'");
        ASSERT_EQ(r.exit_code, 0) << r.output;
        size_t rows = 0;
        for (const std::string& scheme : render::lodSchemeNames())
            rows += r.output.find(scheme + " incremental") != std::string::npos;
        EXPECT_GT(rows, 0u) << r.output;
    }
    EXPECT_GT(tested, 0u);
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

// --bytes-per-view selects in the frame the renderer draws in: on the globe fixture (auto:
// the ellipsoid) the path's cameras are ECEF, thousands of kilometres from the Earth's centre,
// and every frame reads patches; --frame plane flattens it again (and runs as before).
TEST(BenchCli, BytesPerViewRunsOnTheGlobe)
{
    test::ScratchDir dir;
    const std::string arc =
        test::buildWithCli(dir, "etopo5_globe_181x91.tif", "globe.ridge", "--patch 17");
    std::map<std::string, std::vector<double>> first_camera;
    for (const std::string frame : {"auto", "plane"}) {
        const test::CommandResult r = test::runRidgeStdout(
            "bench '" + arc + "' --bytes-per-view --path orbit --frames 5 --json --frame " + frame);
        ASSERT_EQ(r.exit_code, 0) << r.output;
        const nlohmann::json j = nlohmann::json::parse(r.output);
        ASSERT_EQ(j["frames"].size(), 5u);
        for (const auto& f : j["frames"]) {
            EXPECT_GT(f["bytes"].get<uint64_t>(), 0u) << frame;
            const std::vector<double> p = f["position"];
            const double from_centre = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
            if (frame == "auto") {
                EXPECT_GT(from_centre, 6.3e6) << "ECEF, above the ellipsoid";
            }
        }
        first_camera[frame] = j["frames"][0]["position"].get<std::vector<double>>();
    }
    // The two frames place the path differently: --frame reaches the selection.
    const std::vector<double>&a = first_camera["auto"], &b = first_camera["plane"];
    EXPECT_GT(std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]), 1000.0);
}

// The summary and JSON separate frames at full detail from frames drawn coarser and time full
// detail after the start and each teleport (the teleport path jumps every 60 frames);
// without streaming every frame is at full detail, the first one at once.
TEST(BenchCli, SeparatesFramesAtFullDetailAndTimesFullDetailAfterEachTeleport)
{
    test::ScratchDir dir;
    const std::string arc = test::buildEverestWithCli(
        dir, "everest_progressive.ridge", "--patch 33 --codec progressive --max-error 2");
    for (const std::string streaming : {"", " --no-streaming"}) {
        const std::string json = dir.path("teleport.json");
        const test::CommandResult r =
            test::runRidge("bench '" + arc + "' --path teleport --frames 130 --size 160x90" +
                           streaming + " --json-file '" + json + "'");
        ASSERT_EQ(r.exit_code, 0) << r.output;
        for (const char* phrase :
             {"frames at full detail", "frames drawn coarser", "time to full detail      start ",
              "after 2 teleports", "scheme frame time", "warm-up (frame 0)",
              "not measured (--popping measures it)"})
            EXPECT_NE(r.output.find(phrase), std::string::npos) << phrase << " in:\n" << r.output;
        std::ifstream in(json);
        const nlohmann::json j = nlohmann::json::parse(in);
        const nlohmann::json& s = j["summary"];
        int full = 0;
        for (const auto& f : j["frames"]) {
            EXPECT_EQ(f["full_detail"].get<bool>(),
                      f["missing"].get<int>() == 0 && !f["coarser"].get<bool>());
            full += f["full_detail"].get<bool>();
        }
        EXPECT_EQ(s["frames_full_detail"].get<int>(), full);
        EXPECT_EQ(s["frames_full_detail"].get<int>() + s["frames_coarser"].get<int>(), 130);
        EXPECT_EQ(s["full_detail_frame_ms"]["frames"].get<int>(),
                  full - int(j["frames"][0]["full_detail"].get<bool>()));
        EXPECT_EQ(s["full_detail_frame_ms"]["p99"].is_null(),
                  s["full_detail_frame_ms"]["frames"].get<int>() < 100)
            << "a p99 from 100 frames on";
        const nlohmann::json& times = s["time_to_full_detail"];
        ASSERT_EQ(times.size(), 3u);
        int k = 0;
        for (const auto& t : times) {
            EXPECT_EQ(t["frame"].get<int>(), 60 * k);
            EXPECT_EQ(t["after"], k == 0 ? "start" : "teleport");
            if (t["reached"].get<bool>()) {
                const int first = t["frame"].get<int>() + t["frames"].get<int>() - 1;
                EXPECT_TRUE(j["frames"][size_t(first)]["full_detail"].get<bool>());
                EXPECT_GT(t["ms"].get<double>(), 0.0);
            }
            ++k;
        }
        if (!streaming.empty()) {
            EXPECT_EQ(full, 130) << "nothing streams, and 33² patches fit the slots";
            EXPECT_EQ(times[0]["frames"], 1);
        } else {
            EXPECT_GT(s["frames_missing"].get<int>(), 0) << "a teleport streams";
        }
    }
}

// The upload time budget follows the frame time: above a tiny floor once frames are known,
// never above the fraction of the longest frame interval seen; with fraction 0 it is the
// floor.
TEST(BenchCli, UploadTimeBudgetFollowsTheFrameTimeUnlessFixed)
{
    test::ScratchDir dir;
    const std::string arc = buildArchive(dir);
    int most_uploads[2] = {0, 0}; // in one frame: adaptive, fixed
    for (const std::string fraction : {"0.9", "0"}) {
        const std::string json = dir.path("budget.json");
        const test::CommandResult r = test::runRidge(
            "bench '" + arc + "' --path teleport --frames 24 --size 160x90 --upload-ms 0.001 " +
            "--upload-max-ms 1e6 --upload-frame-fraction " + fraction + " --json-file '" + json +
            "'");
        ASSERT_EQ(r.exit_code, 0) << r.output;
        std::ifstream in(json);
        const nlohmann::json j = nlohmann::json::parse(in);
        const auto& frames = j["frames"];
        double longest = 0.0;
        for (size_t k = 0; k < frames.size(); ++k) {
            const double budget = frames[k]["upload_budget_ms"].get<double>();
            if (k > 0)
                longest = std::max(longest, frames[k]["start_ms"].get<double>() -
                                                frames[k - 1]["start_ms"].get<double>());
            // The floor until three frame intervals are known (UploadTimeBudget::kMinFrames).
            if (fraction == "0" || k < 3) {
                EXPECT_EQ(budget, 0.001) << "frame " << k;
            } else {
                EXPECT_GT(budget, 0.001) << "frame " << k;
                EXPECT_LE(budget, 0.9 * longest) << "frame " << k;
            }
            int& most = most_uploads[fraction == "0"];
            most = std::max(most, frames[k]["loaded"].get<int>());
        }
        EXPECT_EQ(j["upload_frame_fraction"].get<double>(), std::stod(fraction));
    }
    // The renderer's upload loop keeps to the budget: a 1 µs one lets only the upload that
    // always goes through; most of a frame's time lets several (a teleport has many waiting).
    EXPECT_EQ(most_uploads[1], 1);
    EXPECT_GT(most_uploads[0], 1);
    for (const std::string bad :
         {"--upload-frame-fraction 1", "--upload-frame-fraction nan", "--upload-max-ms 0"}) {
        const test::CommandResult r = test::runRidge("bench '" + arc + "' --frames 3 " + bad);
        EXPECT_EQ(r.exit_code, 2) << bad << ": " << r.output;
        EXPECT_NE(r.output.find(bad.substr(0, bad.find(' '))), std::string::npos) << r.output;
    }
}
