// Rate-distortion picture of the bench: compression ratio against the L-inf bound, drawn with
// PLplot's pngcairo device through plot::PngPlot. Not thread-safe.
#include "ridge/codecbench/codec_bench.h"

#include "ridge/core/error.h"
#include "ridge/core/file_identity.h"
#include "ridge/io/dataset_files.h"
#include "ridge/plot/png_plot.h"

#include <plplot.h>

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <vector>

namespace ridge::codecbench {

namespace {

using plot::plplotText;

// x is log2 of the bound in metres; ticks read as metres.
void labelBoundAxis(PLINT axis, PLFLT value, char* label, PLINT length, PLPointer)
{
    const std::string text =
        axis == PL_X_AXIS ? fmt::format("{:g}", std::exp2(value)) : fmt::format("{:g}", value);
    std::snprintf(label, size_t(length), "%s", text.c_str());
}

// cmap0: white background, black axes, grey grid, then one distinguishable colour per codec
// (ridge first, in red), Tableau-10 order.
const std::vector<plot::PngPlot::Rgb> kPalette = {
    {255, 255, 255}, {0, 0, 0},      {215, 215, 215}, {214, 39, 40}, {31, 119, 180},
    {255, 127, 14},  {44, 160, 44},  {148, 103, 189}, {140, 86, 75}, {227, 119, 194},
    {127, 127, 127}, {188, 189, 34}, {23, 190, 207}};
const int kPaletteSize = int(kPalette.size());
constexpr int kFirstCurveColour = 3;
constexpr const char* kMarkers[] = {"●", "■", "▲", "◆", "▼", "✚", "★", "⬟", "◀", "▶"};

struct Curve {
    std::string label;
    std::vector<PLFLT> x;
    std::vector<PLFLT> y;
};

} // namespace

void writeCodecBenchPlot(const CodecBenchReport& report, const std::string& path)
{
    refuseOutputOverInput(path, io::datasetFiles(report.input_path));
    // 1. Curves: one per codec, points at every bound > 0 (log2 axis), in bound order.
    std::vector<Curve> curves;
    for (const CodecInfo& c : report.codecs)
        curves.push_back({c.codec, {}, {}});
    for (const BoundResult& b : report.bounds) {
        if (!(b.max_error_metres > 0.0))
            continue;
        for (const CodecRow& row : b.rows)
            for (Curve& c : curves)
                if (c.label == row.codec) {
                    c.x.push_back(std::log2(b.max_error_metres));
                    c.y.push_back(row.ratio);
                }
    }
    for (Curve& c : curves) {
        std::vector<size_t> order(c.x.size());
        for (size_t i = 0; i < order.size(); ++i)
            order[i] = i;
        std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return c.x[a] < c.x[b]; });
        std::vector<PLFLT> x, y;
        for (size_t i : order) {
            x.push_back(c.x[i]);
            y.push_back(c.y[i]);
        }
        c.x = std::move(x);
        c.y = std::move(y);
    }
    double x_min = 0.0, x_max = 0.0, y_max = 0.0;
    bool any = false;
    for (const Curve& c : curves)
        for (size_t i = 0; i < c.x.size(); ++i) {
            x_min = any ? std::min(x_min, c.x[i]) : c.x[i];
            x_max = any ? std::max(x_max, c.x[i]) : c.x[i];
            y_max = std::max(y_max, c.y[i]);
            any = true;
        }
    if (!any)
        throw Error(path + ": nothing to plot (every bound is 0 m, which a log2 axis cannot show)");
    x_min = std::floor(x_min) - 0.5;
    x_max = std::ceil(x_max) + 0.5;
    y_max = y_max > 0.0 ? y_max * 1.08 : 1.0;

    // 2. Device: pngcairo on a stream of its own, into a temporary file.
    plot::PngPlot page(path, 1100, 720, kPalette);

    // 3. Axes: room on the right for the legend.
    pladv(0);
    plvpor(0.09, 0.68, 0.11, 0.86);
    plwind(x_min, x_max, 0.0, y_max);
    plcol0(1);
    plwidth(1.0);
    plslabelfunc(labelBoundAxis, nullptr);
    plschr(0.0, 0.9);
    plcol0(2);
    plbox("g", 1.0, 0, "g", 0.0, 0); // grid first, so the axes and curves draw over it
    plcol0(1);
    plbox("bcnsto", 1.0, 0, "bcnstv", 0.0, 0);
    plslabelfunc(nullptr, nullptr);
    const std::string input = std::filesystem::path(report.input_path).filename().string();
    pllab("L-inf error bound (m, log2 scale)", "compression ratio (16-bit raw / bytes)", "");
    plschr(0.0, 1.1);
    plmtex("t", 3.2, 0.5, 0.5, plplotText("Compression ratio vs error bound: " + input).c_str());
    plschr(0.0, 0.8);
    plmtex("t", 1.6, 0.5, 0.5,
           plplotText(
               fmt::format("{} x {} samples; anchors: finest level, {}; ridge: whole pyramid",
                           report.width, report.height,
                           report.tile_size > 0
                               ? fmt::format("{} x {} tiles", report.tile_size, report.tile_size)
                               : std::string("one tile")))
               .c_str());
    plschr(0.0, 0.9);

    // 4. Curves with markers, and the legend.
    std::vector<PLINT> opts, colours, styles, symbol_numbers;
    std::vector<PLFLT> widths, symbol_scales;
    std::vector<std::string> texts;
    std::vector<const char*> text_ptrs, symbol_ptrs;
    for (size_t i = 0; i < curves.size(); ++i) {
        const Curve& c = curves[i];
        const PLINT colour = PLINT(kFirstCurveColour + i % (kPaletteSize - kFirstCurveColour));
        const char* marker = kMarkers[i % std::size(kMarkers)];
        plcol0(colour);
        plwidth(i == 0 ? 3.0 : 2.0);
        if (c.x.size() > 1)
            plline(PLINT(c.x.size()), c.x.data(), c.y.data());
        plschr(0.0, 1.1);
        if (!c.x.empty())
            plstring(PLINT(c.x.size()), c.x.data(), c.y.data(), marker);
        plschr(0.0, 0.9);
        opts.push_back(PL_LEGEND_LINE | PL_LEGEND_SYMBOL);
        colours.push_back(colour);
        styles.push_back(1);
        widths.push_back(i == 0 ? 3.0 : 2.0);
        symbol_numbers.push_back(1);
        symbol_scales.push_back(1.1);
        texts.push_back(plplotText(c.label));
        symbol_ptrs.push_back(marker);
    }
    for (const std::string& t : texts)
        text_ptrs.push_back(t.c_str());
    plwidth(1.0);
    PLFLT legend_width = 0.0, legend_height = 0.0;
    pllegend(&legend_width, &legend_height, PL_LEGEND_BACKGROUND | PL_LEGEND_BOUNDING_BOX,
             PL_POSITION_OUTSIDE | PL_POSITION_RIGHT | PL_POSITION_VIEWPORT, 0.03, 0.0, 0.06, 0, 1,
             1, 0, 0, PLINT(curves.size()), opts.data(), 1.0, 0.8, 2.0, 0.0, colours.data(),
             text_ptrs.data(), nullptr, nullptr, nullptr, nullptr, colours.data(), styles.data(),
             widths.data(), colours.data(), symbol_scales.data(), symbol_numbers.data(),
             symbol_ptrs.data());

    // 5. Close the stream (writes the PNG), restore the caller's, then publish the file.
    page.commit();
}

} // namespace ridge::codecbench
