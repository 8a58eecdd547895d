#include "ridge/render/legend.h"

#include "ridge/core/error.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace ridge::render {

namespace {

// 3×5 digits, one row of 3 bits per entry, most significant bit left.
constexpr std::array<std::array<uint8_t, 5>, 10> kDigits = {{
    {7, 5, 5, 5, 7}, // 0
    {2, 6, 2, 2, 7}, // 1
    {7, 1, 7, 4, 7}, // 2
    {7, 1, 7, 1, 7}, // 3
    {5, 5, 7, 1, 1}, // 4
    {7, 4, 7, 1, 7}, // 5
    {7, 4, 7, 5, 7}, // 6
    {7, 1, 1, 1, 1}, // 7
    {7, 5, 7, 5, 7}, // 8
    {7, 5, 7, 1, 7}, // 9
}};
constexpr int kScale = 2; // font pixels per glyph bit
constexpr int kGlyphW = 3 * kScale, kGlyphH = 5 * kScale;
constexpr int kSwatch = 12; // pixels
constexpr int kRowH = kSwatch + 4;
static_assert(kGlyphH <= kRowH, "a row's text fits its row");
constexpr int kMargin = 6;

struct Canvas {
    uint8_t* pixels;
    int width, height, channels;
    void fill(int x0, int y0, int w, int h, palette::Rgb c) const
    {
        const uint8_t rgb[3] = {uint8_t(std::lround(std::clamp(c.r, 0.f, 1.f) * 255.f)),
                                uint8_t(std::lround(std::clamp(c.g, 0.f, 1.f) * 255.f)),
                                uint8_t(std::lround(std::clamp(c.b, 0.f, 1.f) * 255.f))};
        for (int y = std::max(y0, 0); y < std::min(y0 + h, height); ++y)
            for (int x = std::max(x0, 0); x < std::min(x0 + w, width); ++x) {
                uint8_t* p = pixels + (size_t(y) * size_t(width) + size_t(x)) * size_t(channels);
                p[0] = rgb[0];
                p[1] = rgb[1];
                p[2] = rgb[2];
                if (channels == 4)
                    p[3] = 255;
            }
    }
    void text(int x, int y, const std::string& digits) const
    {
        for (const char ch : digits) {
            if (ch >= '0' && ch <= '9') {
                const auto& glyph = kDigits[size_t(ch - '0')];
                for (int r = 0; r < 5; ++r)
                    for (int c = 0; c < 3; ++c)
                        if (glyph[size_t(r)] & (4 >> c))
                            fill(x + c * kScale, y + r * kScale, kScale, kScale, {1.f, 1.f, 1.f});
            }
            x += kGlyphW + kScale;
        }
    }
};

int labelWidth(const std::string& s)
{
    return int(s.size()) * (kGlyphW + kScale);
}

} // namespace

std::vector<LegendEntry> legendEntries(DebugMode mode, int finest_level, int block_cells)
{
    std::vector<LegendEntry> entries;
    if (mode == DebugMode::LodLevels) {
        for (int l = 0; l <= std::max(finest_level, 0); ++l)
            entries.push_back({std::to_string(l), palette::levelColour(l)});
    } else if (mode == DebugMode::TessellationFactors) {
        // As terrain.frag: t = log2(factor) / max(log2 b, 1).
        const float log_b = std::max(std::log2(float(std::max(block_cells, 1))), 1.f);
        for (int f = 1; f <= std::max(block_cells, 1); f *= 2)
            entries.push_back({std::to_string(f), palette::heat(std::log2(float(f)) / log_b)});
    }
    return entries;
}

void drawLegend(uint8_t* pixels, int width, int height, int channels,
                const std::vector<LegendEntry>& entries)
{
    if (channels != 3 && channels != 4)
        throw Error("drawLegend: channels is " + std::to_string(channels) + ", expected 3 or 4");
    if (entries.empty() || !pixels)
        return;
    int label_w = 0;
    for (const LegendEntry& e : entries)
        label_w = std::max(label_w, labelWidth(e.label));
    const int cell_w = kSwatch + 4 + label_w + 8;
    const int max_columns = (width - 2 * kMargin) / cell_w;
    if (max_columns < 1 || height < kRowH + 2 * kMargin)
        return;
    const int columns = std::min<int>(max_columns, int(entries.size()));
    const int rows = (int(entries.size()) + columns - 1) / columns;
    const int panel_w = columns * cell_w + 8, panel_h = rows * kRowH + 8;
    const int x0 = kMargin, y0 = std::max(height - kMargin - panel_h, 0);
    const Canvas canvas{pixels, width, height, channels};
    canvas.fill(x0, y0, panel_w, panel_h, {0.08f, 0.08f, 0.10f});
    for (size_t k = 0; k < entries.size(); ++k) {
        const int cx = x0 + 4 + int(k % size_t(columns)) * cell_w;
        const int cy = y0 + 4 + int(k / size_t(columns)) * kRowH;
        canvas.fill(cx, cy + 1, kSwatch, kSwatch, entries[k].colour);
        canvas.text(cx + kSwatch + 4, cy + 2, entries[k].label);
    }
}

} // namespace ridge::render
