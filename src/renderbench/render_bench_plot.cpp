// Frame time along the camera path (PLplot, pngcairo through plot::PngPlot): the picture
// that shows a stall as a spike. Not thread-safe.
#include "ridge/renderbench/render_bench.h"

#include "ridge/core/error.h"
#include "ridge/core/file_identity.h"
#include "ridge/plot/png_plot.h"

#include <plplot.h>

#include <fmt/core.h>

#include <algorithm>
#include <filesystem>
#include <vector>

namespace ridge::renderbench {
void writeRenderBenchPlot(const RenderBenchReport& report, const std::string& path)
{
    refuseOutputOverInput(path, {report.archive, report.options.path.kind});
    if (report.frames.empty())
        throw Error(path + ": no frames to plot");
    std::vector<PLFLT> x, frame, gpu;
    double y_max = 0.0;
    for (size_t k = 0; k < report.frames.size(); ++k) {
        x.push_back(PLFLT(k));
        frame.push_back(report.frames[k].frame_ms);
        gpu.push_back(report.frames[k].gpu_ms);
        y_max = std::max({y_max, report.frames[k].frame_ms, report.frames[k].gpu_ms});
    }
    // Background, axes, grid, frame time, GPU time.
    plot::PngPlot page(
        path, 1100, 600,
        {{255, 255, 255}, {0, 0, 0}, {215, 215, 215}, {214, 39, 40}, {31, 119, 180}});
    pladv(0);
    plvpor(0.08, 0.97, 0.12, 0.86);
    plwind(0.0, double(report.frames.size() - 1), 0.0, y_max > 0.0 ? y_max * 1.1 : 1.0);
    plschr(0.0, 0.9);
    plcol0(2);
    plbox("g", 0.0, 0, "g", 0.0, 0);
    plcol0(1);
    plbox("bcnst", 0.0, 0, "bcnstv", 0.0, 0);
    pllab("frame", "milliseconds", "");
    plschr(0.0, 1.0);
    const std::string title = fmt::format(
        "{} along '{}': frame time (red), GPU terrain pass (blue)",
        std::filesystem::path(report.archive).filename().string(), report.options.path.kind);
    plmtex("t", 2.4, 0.5, 0.5, title.c_str());
    plschr(0.0, 0.8);
    plmtex("t", 1.0, 0.5, 0.5,
           fmt::format("{}x{}, eps {} px, median {:.1f} fps, p99 {:.1f} ms, {}",
                       report.options.viewport.width, report.options.viewport.height,
                       report.options.epsilon_px, report.fps_median, report.frame_ms_p99,
                       report.gl_renderer)
               .c_str());
    plwidth(2.0);
    plcol0(3);
    plline(PLINT(x.size()), x.data(), frame.data());
    plcol0(4);
    plline(PLINT(x.size()), x.data(), gpu.data());
    page.commit();
}

} // namespace ridge::renderbench
