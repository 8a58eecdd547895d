// `ridge bench`'s report from its frames: the summary (frames at full detail against frames
// drawn coarser, time to full detail, the scheme's frame time apart from the warm-up,
// percentiles only where the frames support them) and its text, table and JSON forms.
// GL-free.
#include "ridge/core/json_text.h"
#include "ridge/renderbench/render_bench.h"

#include "ridge/core/atomic_output.h"
#include "ridge/core/error.h"
#include "ridge/core/file_identity.h"
#include "ridge/render/scheme_options.h"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>

namespace ridge::renderbench {
namespace {

// Nearest rank: the ⌈p·n⌉-th smallest (p = 0: the smallest). `v` sorted, not empty.
double nearestRank(const std::vector<double>& v, double p)
{
    const size_t rank = size_t(std::ceil(p * double(v.size())));
    return v[std::min(v.size(), std::max<size_t>(rank, 1)) - 1];
}

// A time to full detail: the first frame at full detail in [first, end).
TimeToFullDetail timeToFullDetail(const std::vector<FrameRecord>& frames, int first, int end)
{
    TimeToFullDetail t;
    t.frame = first;
    t.teleport = first > 0;
    const double start = frames[size_t(first)].start_ms;
    for (int k = first; k < end; ++k) {
        const FrameRecord& f = frames[size_t(k)];
        if (f.fullDetail()) {
            t.frames = k - first + 1;
            t.ms = f.start_ms + f.frame_ms - start;
            return t;
        }
    }
    const FrameRecord& last = frames[size_t(end - 1)];
    t.segment_frames = end - first;
    t.segment_ms = last.start_ms + last.frame_ms - start;
    return t;
}

} // namespace

int framesForPercentile(double p)
{
    return int(std::ceil(1.0 / (1.0 - p) - 1e-9));
}

FrameStatistics frameStatistics(std::vector<double> v)
{
    FrameStatistics s;
    std::erase_if(v, [](double x) { return !std::isfinite(x); });
    s.count = int(v.size());
    if (v.empty())
        return s;
    std::sort(v.begin(), v.end());
    s.median = nearestRank(v, 0.5);
    s.max = v.back();
    if (s.count >= framesForPercentile(0.90))
        s.p90 = nearestRank(v, 0.90);
    if (s.count >= framesForPercentile(0.99))
        s.p99 = nearestRank(v, 0.99);
    return s;
}

std::vector<int> cameraJumpFrames(const RenderBenchOptions& o)
{
    std::vector<int> jumps{0};
    if (o.path.kind == "teleport" && o.path.teleport_every > 0)
        for (int k = o.path.teleport_every; k < o.frames; k += o.path.teleport_every)
            jumps.push_back(k);
    return jumps;
}

void summariseRenderBench(RenderBenchReport& r)
{
    // From the frames alone (what the run measured outside them kept): summarising twice
    // gives the same report.
    RenderBenchReport fresh;
    fresh.archive = std::move(r.archive);
    fresh.gl_renderer = std::move(r.gl_renderer);
    fresh.options = std::move(r.options);
    fresh.frames = std::move(r.frames);
    fresh.ram_cache_bytes = r.ram_cache_bytes;
    fresh.cache_misses = r.cache_misses;
    r = std::move(fresh);
    if (r.frames.empty())
        return;
    std::vector<double> all, full, coarser, budgets, popping;
    double total_ms = 0.0, triangles = 0.0;
    for (size_t k = 0; k < r.frames.size(); ++k) {
        const FrameRecord& f = r.frames[k];
        all.push_back(f.frame_ms);
        // Frame 0 is the warm-up whatever it drew: shaders compile, buffers grow, and
        // without streaming every patch of the view loads in it.
        if (k > 0)
            (f.fullDetail() ? full : coarser).push_back(f.frame_ms);
        if (f.upload_budget_ms > 0.0)
            budgets.push_back(f.upload_budget_ms);
        if (f.popping_px >= 0)
            popping.push_back(f.popping_px);
        r.popping_sample_stride = std::max(r.popping_sample_stride, f.popping_sample_stride);
        total_ms += f.frame_ms;
        triangles += double(f.triangles);
        r.frames_full_detail += f.fullDetail();
        r.frames_missing += f.missing > 0;
        r.frames_epsilon_raised += f.coarser;
        r.select_ms_max = std::max(r.select_ms_max, f.select_ms);
        r.hole_pixels += f.hole_pixels;
        r.frames_with_holes += f.hole_pixels > 0;
        r.bytes_read += f.bytes_read;
        r.bytes_decoded += f.bytes_decoded;
        r.bytes_uploaded += f.bytes_uploaded;
        r.reconstructed += f.reconstructed;
        r.refined += f.refined;
        r.refine_steps += f.refine_steps;
        r.frames_under_refined += f.under_refined > 0;
        r.level_shifts_per_frame += double(f.level_shifts) / double(r.frames.size());
        r.samples_written += f.samples_written;
        r.frames_levels_waiting += f.levels_drawn < f.levels_wanted;
    }
    r.frames_coarser = int(r.frames.size()) - r.frames_full_detail;
    r.warmup_ms = r.frames.front().frame_ms;
    r.full_detail_ms = frameStatistics(std::move(full));
    r.coarser_ms = frameStatistics(std::move(coarser));
    r.upload_budget_ms = frameStatistics(std::move(budgets));
    r.popping_px = frameStatistics(std::move(popping));
    const std::vector<int> jumps = cameraJumpFrames(r.options);
    for (size_t k = 0; k < jumps.size() && jumps[k] < int(r.frames.size()); ++k)
        r.time_to_full_detail.push_back(
            timeToFullDetail(r.frames, jumps[k],
                             k + 1 < jumps.size() ? std::min(jumps[k + 1], int(r.frames.size()))
                                                  : int(r.frames.size())));

    r.all_ms = frameStatistics(all);
    std::sort(all.begin(), all.end());
    auto fps = [](double frame_ms) { return frame_ms > 0.0 ? 1000.0 / frame_ms : 0.0; };
    r.fps_min = fps(all.back());
    r.fps_median = fps(r.all_ms.median);
    r.fps_max = fps(all.front());
    r.rss_early_mib = r.frames[r.frames.size() / 10].rss_mib;
    r.rss_end_mib = r.frames.back().rss_mib;
    r.frames_over_twice_median = int(
        std::count_if(all.begin(), all.end(), [&](double m) { return m > 2.0 * r.all_ms.median; }));
    r.mtri_per_s = total_ms > 0.0 ? triangles / (total_ms * 1e3) : 0.0;
    r.triangles_mean = triangles / double(r.frames.size());
}

namespace {

// "median 152.3 ms over 22 frames, p90 160.1, p99 — (needs 100 frames), max 170.0 ms":
// every figure with the frames it rests on, and no percentile those frames cannot support.
std::string describe(const FrameStatistics& s, const char* unit, int decimals)
{
    if (s.count == 0)
        return "no frames";
    auto number = [&](double v) { return fmt::format("{:.{}f}", v, decimals); };
    auto percentile = [&](const char* name, double v, double p) {
        return std::isfinite(v)
                   ? fmt::format(", {} {}", name, number(v))
                   : fmt::format(", {} — (needs {} frames)", name, framesForPercentile(p));
    };
    return fmt::format("median {} {} over {} frame{}{}{}, max {} {}", number(s.median), unit,
                       s.count, s.count == 1 ? "" : "s", percentile("p90", s.p90, 0.90),
                       percentile("p99", s.p99, 0.99), number(s.max), unit);
}

std::string seconds(double ms)
{
    return fmt::format("{:.2f} s", ms / 1000.0);
}

// "start 14.21 s (37 frames); after 4 teleports: 4 reached, median 3.10 s, max 5.20 s ..."
std::string describeTimeToFullDetail(const RenderBenchReport& r)
{
    if (r.time_to_full_detail.empty())
        return "no frames";
    auto one = [](const TimeToFullDetail& t) {
        return t.frames > 0 ? fmt::format("{} ({} frame{})", seconds(t.ms), t.frames,
                                          t.frames == 1 ? "" : "s")
                            : fmt::format("not reached in {} frames ({})", t.segment_frames,
                                          seconds(t.segment_ms));
    };
    std::string out = "start " + one(r.time_to_full_detail.front());
    std::vector<double> reached;
    int teleports = 0, frames_max = 0;
    for (const TimeToFullDetail& t : r.time_to_full_detail)
        if (t.teleport) {
            ++teleports;
            if (t.frames > 0) {
                reached.push_back(t.ms);
                frames_max = std::max(frames_max, t.frames);
            }
        }
    if (teleports == 0)
        return out;
    out += fmt::format("; after {} teleport{}: {} reached", teleports, teleports == 1 ? "" : "s",
                       reached.size());
    if (!reached.empty()) {
        const FrameStatistics s = frameStatistics(reached);
        out += fmt::format(", median {}, max {} (at most {} frames)", seconds(s.median),
                           seconds(s.max), frames_max);
    }
    return out;
}

// How much of the texture detail the frames wanted was resident (nothing when none was).
std::string describeTextureDetail(const RenderBenchReport& r)
{
    double wanted = 0.0, resident = 0.0;
    for (const FrameRecord& f : r.frames) {
        wanted += f.detail;
        resident += f.detail_resident;
    }
    if (wanted == 0.0)
        return "  texture detail           none wanted\n";
    const double n = double(r.frames.size());
    return fmt::format(
        "  texture detail           {:.1f} of {:.1f} patches resident a frame ({:.0f} %)\n",
        resident / n, wanted / n, 100.0 * resident / wanted);
}

} // namespace

std::string formatRenderBenchSummary(const RenderBenchReport& r)
{
    auto mib = [](uint64_t bytes) { return double(bytes) / (1024.0 * 1024.0); };
    const render::RendererOptions& ro = r.options.renderer;
    const double scheme_fps = r.full_detail_ms.count > 0 && r.full_detail_ms.median > 0
                                  ? 1000.0 / r.full_detail_ms.median
                                  : 0.0;
    const std::string budget =
        !ro.streaming ? std::string("not streaming")
        : r.upload_budget_ms.count == 0
            ? std::string("no frames")
            : fmt::format("median {:.1f} ms, max {:.1f} ms ({})", r.upload_budget_ms.median,
                          r.upload_budget_ms.max,
                          ro.upload_frame_fraction > 0
                              ? fmt::format("{} of the frame time, {} to {} ms",
                                            ro.upload_frame_fraction, ro.upload_budget_ms,
                                            std::max(ro.upload_budget_ms, ro.upload_budget_max_ms))
                              : fmt::format("fixed {} ms", ro.upload_budget_ms));
    const std::string summary = fmt::format(
        "{}: {}, path {}, {} frames at {}x{}, ε {} px, culling {}, {}\n"
        "  frames at full detail    {} of {} (nothing drawn by an ancestor, ε as asked)\n"
        "  frames drawn coarser     {}: {} still streaming (patches drawn by an ancestor), {} at "
        "a raised ε (more patches in view than texture slots)\n"
        "  time to full detail      {}\n"
        "  scheme frame time        {}\n"
        "                           at full detail, frame 0 left out{}\n"
        "  coarser frames' time     {}\n"
        "  warm-up (frame 0)        {:.1f} ms\n"
        "  fps min / median / max   {:.1f} / {:.1f} / {:.1f} (all frames: warm-up and coarser "
        "ones too)\n"
        "  frame time, all frames   {}\n"
        "  frames over 2x median    {} (of all frames)\n"
        "  upload time budget       {}\n"
        "  triangles                {:.2f} Mtri/s\n"
        "  CPU selection, worst     {:.3f} ms\n"
        "  RAM caches at the end    {:.1f} MiB\n"
        "  resident memory          {:.1f} MiB after {} frames, {:.1f} MiB at the end\n"
        "  read / decoded / upload  {:.1f} / {:.1f} / {:.1f} MiB ({} patches "
        "reconstructed on the GPU)\n"
        "  refined in place         {} patches, {} iterations; {} frames drew a patch short "
        "of its iterations\n"
        "  level shifts             {:.2f} a frame, {} window samples written; {} frames drew "
        "fewer levels than the view wants\n"
        "  hole pixels              {} in {} frames\n"
        "  popping                  {}\n",
        r.archive, r.options.scheme, r.options.path.kind, r.frames.size(), r.options.viewport.width,
        r.options.viewport.height, r.options.epsilon_px, r.options.cull ? "on" : "off",
        r.gl_renderer, r.frames_full_detail, r.frames.size(), r.frames_coarser, r.frames_missing,
        r.frames_epsilon_raised, describeTimeToFullDetail(r), describe(r.full_detail_ms, "ms", 1),
        scheme_fps > 0 ? fmt::format(": {:.1f} fps", scheme_fps)
                       : std::string(": no frame at full detail, no frame rate claimed"),
        describe(r.coarser_ms, "ms", 1), r.warmup_ms, r.fps_min, r.fps_median, r.fps_max,
        describe(r.all_ms, "ms", 1), r.frames_over_twice_median, budget, r.mtri_per_s,
        r.select_ms_max, mib(r.ram_cache_bytes), r.rss_early_mib, r.frames.size() / 10 + 1,
        r.rss_end_mib, mib(r.bytes_read), mib(r.bytes_decoded), mib(r.bytes_uploaded),
        r.reconstructed, r.refined, r.refine_steps, r.frames_under_refined,
        r.level_shifts_per_frame, r.samples_written, r.frames_levels_waiting, r.hole_pixels,
        r.frames_with_holes,
        r.popping_px.count == 0
            ? std::string("not measured (--popping measures it)")
            : describe(r.popping_px, "px", 3) +
                  (r.popping_sample_stride > 1
                       ? fmt::format(" (one sample in {} along each axis)", r.popping_sample_stride)
                       : std::string()));
    return summary + describeTextureDetail(r);
}

std::string formatRenderBenchTable(const std::vector<RenderBenchReport>& reports)
{
    std::string out = fmt::format("{:<44} {:>8} {:>8} {:>8} {:>10} {:>11} {:>8} {:>10} {:>7}\n",
                                  "approach", "FPS min", "FPS max", "FPS med", "cache miss",
                                  "triangles", "Mtri/s", "select ms", "coarser");
    for (const RenderBenchReport& r : reports) {
        // Streamed rows are the paper's "Base incremental": decoded on the GPU, far patches
        // with fewer iterations, refined in place.
        const std::string name =
            fmt::format("{}{}{}", r.options.scheme, r.options.cull ? "" : " without frustum",
                        r.options.renderer.streaming ? " incremental" : "");
        // CPU time of selection and culling, the median frame (the paper: negligible).
        std::vector<double> select;
        for (const FrameRecord& f : r.frames)
            select.push_back(f.select_ms);
        const FrameStatistics s = frameStatistics(select);
        out += fmt::format(
            "{:<44} {:>8.1f} {:>8.1f} {:>8.1f} {:>10} {:>11.0f} {:>8.1f} {:>10.3f} {:>7}\n", name,
            r.fps_min, r.fps_max, r.fps_median, r.cache_misses, r.triangles_mean, r.mtri_per_s,
            s.median, r.frames_coarser);
    }
    return out;
}

namespace {

// A figure the frames cannot support (NaN) is null, not a number.
nlohmann::json number(double v)
{
    return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

nlohmann::json statistics(const FrameStatistics& s)
{
    return {{"frames", s.count},
            {"median", number(s.median)},
            {"p90", number(s.p90)},
            {"p99", number(s.p99)},
            {"max", number(s.max)}};
}

} // namespace

std::string formatRenderBenchJson(const RenderBenchReport& r)
{
    nlohmann::json frames = nlohmann::json::array();
    for (const FrameRecord& f : r.frames)
        frames.push_back({{"start_ms", f.start_ms},
                          {"frame_ms", f.frame_ms},
                          {"full_detail", f.fullDetail()},
                          {"select_ms", f.select_ms},
                          {"load_ms", f.load_ms},
                          {"gpu_ms", f.gpu_ms},
                          {"upload_budget_ms", f.upload_budget_ms},
                          {"triangles", f.triangles},
                          {"patches", f.patches},
                          {"missing", f.missing},
                          {"detail", f.detail},
                          {"detail_resident", f.detail_resident},
                          {"fading", f.fading},
                          {"loaded", f.loaded},
                          {"reconstructed", f.reconstructed},
                          {"refined", f.refined},
                          {"refine_steps", f.refine_steps},
                          {"under_refined", f.under_refined},
                          {"level_shifts", f.level_shifts},
                          {"levels_drawn", f.levels_drawn},
                          {"levels_wanted", f.levels_wanted},
                          {"samples_written", f.samples_written},
                          {"epsilon_px", f.epsilon_px},
                          {"coarser", f.coarser},
                          {"cache_hits", f.cache_hits},
                          {"cache_misses", f.cache_misses},
                          {"bytes_read", f.bytes_read},
                          {"bytes_decoded", f.bytes_decoded},
                          {"bytes_uploaded", f.bytes_uploaded},
                          {"rss_mib", f.rss_mib},
                          {"ram_cache_mib", f.ram_cache_mib},
                          {"hole_pixels", f.hole_pixels},
                          {"footprint_pixels", f.footprint_pixels},
                          {"popping_px", f.popping_px},
                          {"popping_sample_stride", f.popping_sample_stride}});
    nlohmann::json to_full = nlohmann::json::array();
    for (const TimeToFullDetail& t : r.time_to_full_detail)
        to_full.push_back({{"frame", t.frame},
                           {"after", t.teleport ? "teleport" : "start"},
                           {"reached", t.frames > 0},
                           {"frames", t.frames > 0 ? nlohmann::json(t.frames) : nullptr},
                           {"ms", number(t.ms)},
                           {"segment_frames", t.frames > 0 ? nlohmann::json(nullptr)
                                                           : nlohmann::json(t.segment_frames)},
                           {"segment_ms", t.frames > 0 ? nlohmann::json(nullptr)
                                                       : nlohmann::json(t.segment_ms)}});
    const render::RendererOptions& ro = r.options.renderer;
    const render::SchemeOptions options = render::parseSchemeSpec(r.options.scheme);
    const nlohmann::json j = {
        {"archive", r.archive},
        {"gl_renderer", r.gl_renderer},
        {"renderer", options.scheme()},
        {"scheme_spec", options.spec()}, // every option of the scheme, defaults included
        {"path", r.options.path.kind},
        {"speed_mps", r.options.path.speed_mps},
        {"height_above_ground_m", r.options.path.height_above_ground},
        {"size", {r.options.viewport.width, r.options.viewport.height}},
        {"epsilon_px", r.options.epsilon_px},
        {"texel_px", r.options.texel_px},
        {"cull", r.options.cull},
        {"streaming", ro.streaming},
        {"hole_pixels", r.hole_pixels},
        {"frames_with_holes", r.frames_with_holes},
        {"popping_p99_px", number(r.popping_px.p99)},
        {"popping_max_px", number(r.popping_px.max)},
        {"gpu_reconstruction", ro.gpu_reconstruction},
        {"ram_mb", ro.ram_budget_mb},
        {"vram_mb", ro.vram_budget_mb},
        {"upload_mb", ro.upload_budget_mb},
        {"upload_ms", ro.upload_budget_ms},
        {"upload_frame_fraction", ro.upload_frame_fraction},
        {"upload_max_ms", ro.upload_budget_max_ms},
        {"summary",
         {// Full detail against coarser, and the scheme's frame time over the first.
          {"frames_full_detail", r.frames_full_detail},
          {"frames_coarser", r.frames_coarser},
          {"frames_missing", r.frames_missing},
          {"frames_epsilon_raised", r.frames_epsilon_raised},
          {"time_to_full_detail", to_full},
          {"full_detail_frame_ms", statistics(r.full_detail_ms)},
          {"scheme_fps", r.full_detail_ms.count > 0 && r.full_detail_ms.median > 0
                             ? nlohmann::json(1000.0 / r.full_detail_ms.median)
                             : nlohmann::json(nullptr)},
          {"coarser_frame_ms", statistics(r.coarser_ms)},
          {"warmup_frame_ms", r.warmup_ms},
          {"upload_budget_ms", statistics(r.upload_budget_ms)},
          {"popping_px", statistics(r.popping_px)},
          {"popping_sample_stride", r.popping_sample_stride},
          // Over all frames, warm-up and coarser ones included.
          {"all_frame_ms", statistics(r.all_ms)},
          {"fps_min", r.fps_min},
          {"fps_median", r.fps_median},
          {"fps_max", r.fps_max},
          {"frame_ms_p99", number(r.all_ms.p99)},
          {"frame_ms_max", number(r.all_ms.max)},
          {"frames_over_twice_median", r.frames_over_twice_median},
          {"bytes_read", r.bytes_read},
          {"bytes_decoded", r.bytes_decoded},
          {"bytes_uploaded", r.bytes_uploaded},
          {"reconstructed", r.reconstructed},
          {"refined", r.refined},
          {"refine_steps", r.refine_steps},
          {"frames_under_refined", r.frames_under_refined},
          {"level_shifts_per_frame", r.level_shifts_per_frame},
          {"samples_written", r.samples_written},
          {"frames_levels_waiting", r.frames_levels_waiting},
          {"rss_early_mib", r.rss_early_mib},
          {"rss_end_mib", r.rss_end_mib},
          {"mtri_per_s", r.mtri_per_s},
          {"select_ms_max", r.select_ms_max},
          {"ram_cache_bytes", r.ram_cache_bytes},
          {"cache_misses", r.cache_misses},
          {"triangles_mean", r.triangles_mean}}},
        {"frames", frames}};
    return jsonText(j, 1) + "\n";
}

void writeRenderBenchJson(const RenderBenchReport& r, const std::string& path)
{
    refuseOutputOverInput(path, {r.archive, r.options.path.kind}); // kind: maybe a pose file
    writeFileAtomically(path, formatRenderBenchJson(r));
}

} // namespace ridge::renderbench
