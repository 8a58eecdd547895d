// Frame time along the camera path (PLplot, pngcairo through plot::PngPlot): the picture
// that shows a stall as a spike, and which frames were at full detail (the scheme's own
// frames) and which were drawn coarser while streaming. Not thread-safe.
#include "ridge/renderbench/render_bench.h"

#include "ridge/core/error.h"
#include "ridge/core/file_identity.h"
#include "ridge/plot/png_plot.h"

#include <plplot.h>

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <vector>

namespace ridge::renderbench {

std::vector<std::string> renderBenchPlotTitles(const RenderBenchReport& r)
{
    const RenderBenchOptions& o = r.options;
    std::string title = fmt::format("{} on {}, {}x{}, ε {} px, path '{}'{}", o.scheme,
                                    std::filesystem::path(r.archive).filename().string(),
                                    o.viewport.width, o.viewport.height, o.epsilon_px, o.path.kind,
                                    o.renderer.streaming ? "" : ", no streaming");
    std::string detail =
        fmt::format("{} of {} frames at full detail", r.frames_full_detail, r.frames.size());
    if (r.full_detail_ms.count > 0)
        detail += fmt::format(", median {:.1f} ms over {} (frame 0 left out)",
                              r.full_detail_ms.median, r.full_detail_ms.count);
    if (!r.time_to_full_detail.empty()) {
        const TimeToFullDetail& t = r.time_to_full_detail.front();
        detail += t.frames > 0
                      ? fmt::format("; full detail {:.2f} s after the start", t.ms / 1000.0)
                      : std::string("; full detail not reached from the start");
    }
    return {std::move(title), std::move(detail),
            "frame time (red; green dots: frames at full detail), GPU terrain pass (blue); " +
                r.gl_renderer};
}

void writeRenderBenchPlot(const RenderBenchReport& report, const std::string& path)
{
    refuseOutputOverInput(path, {report.archive, report.options.path.kind});
    if (report.frames.empty())
        throw Error(path + ": no frames to plot");
    std::vector<PLFLT> x, frame, gpu, full_x, full_y;
    double y_max = 0.0;
    for (size_t k = 0; k < report.frames.size(); ++k) {
        const FrameRecord& f = report.frames[k];
        x.push_back(PLFLT(k));
        frame.push_back(f.frame_ms);
        gpu.push_back(f.gpu_ms);
        if (f.fullDetail()) {
            full_x.push_back(PLFLT(k));
            full_y.push_back(f.frame_ms);
        }
        y_max = std::max({y_max, f.frame_ms, f.gpu_ms});
    }
    // Background, axes, grid, frame time, GPU time, frames at full detail.
    plot::PngPlot page(path, 1100, 600,
                       {{255, 255, 255},
                        {0, 0, 0},
                        {215, 215, 215},
                        {214, 39, 40},
                        {31, 119, 180},
                        {44, 160, 44}});
    pladv(0);
    plvpor(0.08, 0.97, 0.12, 0.84);
    plwind(0.0, std::max(1.0, double(report.frames.size() - 1)), 0.0,
           y_max > 0.0 ? y_max * 1.1 : 1.0);
    plschr(0.0, 0.9);
    plcol0(2);
    plbox("g", 0.0, 0, "g", 0.0, 0);
    plcol0(1);
    plbox("bcnst", 0.0, 0, "bcnstv", 0.0, 0);
    pllab("frame", "milliseconds", "");
    const std::vector<std::string> titles = renderBenchPlotTitles(report);
    plschr(0.0, 1.0);
    plmtex("t", 3.6, 0.5, 0.5, plot::plplotText(titles[0]).c_str());
    plschr(0.0, 0.8);
    plmtex("t", 2.2, 0.5, 0.5, plot::plplotText(titles[1]).c_str());
    plmtex("t", 0.8, 0.5, 0.5, plot::plplotText(titles[2]).c_str());
    plwidth(2.0);
    plcol0(3);
    plline(PLINT(x.size()), x.data(), frame.data());
    plcol0(4);
    plline(PLINT(x.size()), x.data(), gpu.data());
    if (!full_x.empty()) {
        plcol0(5);
        plssym(0.0, 0.8);
        plpoin(PLINT(full_x.size()), full_x.data(), full_y.data(), 17); // filled dot
    }
    page.commit();
}

} // namespace ridge::renderbench
