// `ridge bench`'s summary from its frames, without GL: frames at full detail against frames
// drawn coarser, time to full detail after the start and after each teleport, the scheme's
// frame time apart from the warm-up, percentiles only where the frames support them, and
// text that names the scheme, the archive and the flags.
#include "ridge/render/terrain_renderer.h"
#include "ridge/renderbench/render_bench.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <numeric>

using namespace ridge;
using namespace ridge::renderbench;

namespace {

// A frame `ms` long starting at `start_ms`, with `missing` patches drawn by an ancestor.
FrameRecord frameAt(double start_ms, double ms, int missing, bool coarser = false)
{
    FrameRecord f;
    f.start_ms = start_ms;
    f.frame_ms = ms;
    f.missing = missing;
    f.coarser = coarser;
    f.patches = 10;
    f.triangles = 1000;
    return f;
}

// A teleport run of 30 frames, a jump every 10: full detail at frame 4 after the start, at
// frame 13 after the first jump, never after the second. Frames start every 100 ms; frame 0
// (the warm-up) takes 4 s, those at full detail 50 ms, the others 80 ms; frame 6 is at a
// raised ε.
RenderBenchReport teleportRun()
{
    RenderBenchReport r;
    r.archive = "/data/sierra #2.ridge";
    r.gl_renderer = "llvmpipe (test)";
    r.options.scheme = render::lodSchemeNames().back();
    r.options.path.kind = "teleport";
    r.options.path.teleport_every = 10;
    r.options.frames = 30;
    r.options.viewport = {640, 360};
    r.options.epsilon_px = 2.0;
    double start = 0.0;
    for (int k = 0; k < 30; ++k) {
        const int segment = k / 10, in = k % 10;
        const bool full = (segment == 0 && in >= 4 && k != 6) || (segment == 1 && in >= 3);
        const double ms = k == 0 ? 4000.0 : full ? 50.0 : 80.0;
        r.frames.push_back(frameAt(start, ms, full || k == 6 ? 0 : 5 - in % 5 + 1, k == 6));
        start += std::max(ms, 100.0);
    }
    summariseRenderBench(r);
    return r;
}

} // namespace

TEST(RenderBenchSummary, SeparatesFramesAtFullDetailFromFramesDrawnCoarser)
{
    const RenderBenchReport r = teleportRun();
    // Segment 0: frames 4, 5, 7, 8, 9; segment 1: 13..19; segment 2: none.
    EXPECT_EQ(r.frames_full_detail, 12);
    EXPECT_EQ(r.frames_coarser, 18);
    EXPECT_EQ(r.frames_epsilon_raised, 1);
    EXPECT_EQ(r.frames_missing, 17);
    // The scheme's frame time: frames at full detail only, the warm-up apart.
    EXPECT_EQ(r.full_detail_ms.count, 12);
    EXPECT_DOUBLE_EQ(r.full_detail_ms.median, 50.0);
    EXPECT_DOUBLE_EQ(r.full_detail_ms.max, 50.0);
    EXPECT_EQ(r.coarser_ms.count, 17); // frame 0 left out
    EXPECT_DOUBLE_EQ(r.coarser_ms.max, 80.0);
    EXPECT_DOUBLE_EQ(r.warmup_ms, 4000.0);
    EXPECT_DOUBLE_EQ(r.all_ms.max, 4000.0);
}

TEST(RenderBenchSummary, TimesFullDetailAfterTheStartAndAfterEachTeleport)
{
    const RenderBenchReport r = teleportRun();
    ASSERT_EQ(r.time_to_full_detail.size(), 3u);
    const TimeToFullDetail& start = r.time_to_full_detail[0];
    EXPECT_FALSE(start.teleport);
    EXPECT_EQ(start.frame, 0);
    EXPECT_EQ(start.frames, 5); // frames 0..4
    // Frame 4 starts at 4000 + 3·100 ms and lasts 50 ms.
    EXPECT_DOUBLE_EQ(start.ms, 4350.0);
    const TimeToFullDetail& first = r.time_to_full_detail[1];
    EXPECT_TRUE(first.teleport);
    EXPECT_EQ(first.frame, 10);
    EXPECT_EQ(first.frames, 4); // frames 10..13
    EXPECT_DOUBLE_EQ(first.ms, 350.0);
    const TimeToFullDetail& second = r.time_to_full_detail[2];
    EXPECT_EQ(second.frame, 20);
    EXPECT_EQ(second.frames, -1);
    EXPECT_TRUE(std::isnan(second.ms));
    EXPECT_EQ(second.segment_frames, 10);
    EXPECT_DOUBLE_EQ(second.segment_ms, 9 * 100.0 + 80.0);
    // Without teleports: the start alone, over the whole run.
    RenderBenchReport flyover = r;
    flyover.options.path.kind = "flyover";
    summariseRenderBench(flyover);
    ASSERT_EQ(flyover.time_to_full_detail.size(), 1u);
    EXPECT_EQ(flyover.time_to_full_detail[0].frames, 5);
}

TEST(RenderBenchSummary, ClaimsAPercentileOnlyWhereTheFramesSupportIt)
{
    std::vector<double> hundred(100);
    std::iota(hundred.begin(), hundred.end(), 1.0);
    const FrameStatistics s = frameStatistics(hundred);
    EXPECT_EQ(s.count, 100);
    EXPECT_DOUBLE_EQ(s.median, 50.0);
    EXPECT_DOUBLE_EQ(s.p90, 90.0);
    EXPECT_DOUBLE_EQ(s.p99, 99.0); // not the worst frame
    EXPECT_DOUBLE_EQ(s.max, 100.0);
    // 60 frames: a "p99" would be the worst one (often the warm-up), so none is claimed.
    const FrameStatistics sixty =
        frameStatistics(std::vector<double>(hundred.begin(), hundred.begin() + 60));
    EXPECT_TRUE(std::isnan(sixty.p99));
    EXPECT_DOUBLE_EQ(sixty.p90, 54.0);
    EXPECT_TRUE(std::isnan(frameStatistics({1, 2, 3}).p90));
    EXPECT_EQ(frameStatistics({}).count, 0);
    EXPECT_TRUE(std::isnan(frameStatistics({}).median));
    EXPECT_EQ(framesForPercentile(0.99), 100);
    EXPECT_EQ(framesForPercentile(0.90), 10);
}

TEST(RenderBenchSummary, TextAndJsonSayWhatTheFiguresRestOn)
{
    const RenderBenchReport r = teleportRun();
    const std::string text = formatRenderBenchSummary(r);
    for (const std::string phrase :
         {"frames at full detail    12 of 30", "frames drawn coarser     18: 17 still streaming",
          "1 at a raised ε", "start 4.35 s (5 frames)",
          "after 2 teleports: 1 reached, median 0.35 s", "median 50.0 ms over 12 frames",
          "p90 50.0", "p99 — (needs 100 frames)", ": 20.0 fps", "warm-up (frame 0)        4000.0",
          "not measured (--popping measures it)"})
        EXPECT_NE(text.find(phrase), std::string::npos) << "'" << phrase << "' in:\n" << text;
    EXPECT_EQ(text.find("measure_popping"), std::string::npos) << "an internal name:\n" << text;
    EXPECT_NE(text.find(r.options.scheme), std::string::npos);

    const nlohmann::json j = nlohmann::json::parse(formatRenderBenchJson(r));
    const nlohmann::json& s = j["summary"];
    EXPECT_EQ(s["frames_full_detail"], 12);
    EXPECT_EQ(s["frames_coarser"], 18);
    EXPECT_EQ(s["full_detail_frame_ms"]["frames"], 12);
    EXPECT_DOUBLE_EQ(s["full_detail_frame_ms"]["median"].get<double>(), 50.0);
    EXPECT_TRUE(s["full_detail_frame_ms"]["p99"].is_null());
    EXPECT_TRUE(s["frame_ms_p99"].is_null()) << "30 frames have no p99";
    EXPECT_DOUBLE_EQ(s["scheme_fps"].get<double>(), 20.0);
    EXPECT_DOUBLE_EQ(s["warmup_frame_ms"].get<double>(), 4000.0);
    ASSERT_EQ(s["time_to_full_detail"].size(), 3u);
    EXPECT_EQ(s["time_to_full_detail"][0]["after"], "start");
    EXPECT_EQ(s["time_to_full_detail"][0]["frames"], 5);
    EXPECT_EQ(s["time_to_full_detail"][1]["after"], "teleport");
    EXPECT_DOUBLE_EQ(s["time_to_full_detail"][1]["ms"].get<double>(), 350.0);
    EXPECT_FALSE(s["time_to_full_detail"][2]["reached"].get<bool>());
    EXPECT_TRUE(s["time_to_full_detail"][2]["ms"].is_null());
    EXPECT_EQ(s["time_to_full_detail"][2]["segment_frames"], 10);
    EXPECT_EQ(j["frames"][4]["full_detail"], true);
    EXPECT_EQ(j["frames"][6]["full_detail"], false);

    // Popping, measured on fewer than 100 frames: its max, no p99.
    RenderBenchReport popped = r;
    for (size_t k = 1; k < popped.frames.size(); ++k) {
        popped.frames[k].popping_px = 0.01 * double(k);
        popped.frames[k].popping_sample_stride = 1;
    }
    summariseRenderBench(popped);
    const std::string popping = formatRenderBenchSummary(popped);
    EXPECT_NE(popping.find("max 0.290 px"), std::string::npos) << popping;
    EXPECT_NE(popping.find("over 29 frames"), std::string::npos) << popping;
    EXPECT_EQ(popping.find("one sample in"), std::string::npos) << "every sample compared";
    // A frame whose window was thinned says so.
    popped.frames[7].popping_sample_stride = 3;
    summariseRenderBench(popped);
    EXPECT_EQ(popped.popping_sample_stride, 3);
    const std::string thinned = formatRenderBenchSummary(popped);
    EXPECT_NE(thinned.find("(one sample in 3 along each axis)"), std::string::npos) << thinned;
}

TEST(RenderBenchSummary, WithoutAFrameAtFullDetailNoFrameRateIsClaimed)
{
    RenderBenchReport r = teleportRun();
    for (FrameRecord& f : r.frames)
        f.missing = 3;
    summariseRenderBench(r);
    EXPECT_EQ(r.frames_full_detail, 0);
    const std::string text = formatRenderBenchSummary(r);
    EXPECT_NE(text.find("no frame at full detail, no frame rate claimed"), std::string::npos)
        << text;
    EXPECT_NE(text.find("start not reached in 10 frames"), std::string::npos) << text;
    EXPECT_TRUE(nlohmann::json::parse(formatRenderBenchJson(r))["summary"]["scheme_fps"].is_null());
}

TEST(RenderBenchSummary, PlotTitlesNameTheSchemeArchiveSizeAndEpsilon)
{
    for (const std::string& scheme : render::lodSchemeNames()) {
        RenderBenchReport r = teleportRun();
        r.options.scheme = scheme;
        summariseRenderBench(r);
        const std::vector<std::string> titles = renderBenchPlotTitles(r);
        ASSERT_EQ(titles.size(), 3u);
        for (const std::string& phrase : {scheme + " on sierra #2.ridge", std::string("640x360"),
                                          std::string("ε 2 px"), std::string("path 'teleport'")})
            EXPECT_NE(titles[0].find(phrase), std::string::npos) << phrase << " in " << titles[0];
        EXPECT_NE(titles[1].find("12 of 30 frames at full detail"), std::string::npos) << titles[1];
        EXPECT_NE(titles[2].find("llvmpipe (test)"), std::string::npos) << titles[2];
    }
}
