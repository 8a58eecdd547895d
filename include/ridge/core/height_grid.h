#pragma once
// The in-memory elevation model: a grid of 16-bit codes plus the code -> metre mapping.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace ridge {

// The largest |metres| of any height, and the largest ground spacing between samples, that
// ridge accepts anywhere (ingest, archive fields, parameters). Nothing real reaches them: no
// relief on any planet, and no useful grid spacing, exceeds the Earth's radius (6.4e6 m);
// values beyond are a unit mistake or a hostile file. Within them every height, sum and
// extent stays finite in float and double.
inline constexpr double kMaxAbsHeightMetres = 1e7;
inline constexpr double kMaxSpacingMetres = 1e7;

// metres = offset + scale * code. `max_error` is the largest |metres(code) - source value|
// over all valid (non-void) source samples, measured during quantization (0 when exact).
struct HeightQuantization {
    double scale = 1.0;
    double offset = 0.0;
    double max_error = 0.0;

    double toMetres(double code) const { return offset + scale * code; }
};

// Row-major grid of codes. 2 bytes per sample: the finest grid of a 10801x4801 raster is
// 104 MB, which is why the pyramid keeps codes (not floats) and views (not copies).
struct CodeGrid {
    int width = 0;
    int height = 0;
    std::vector<uint16_t> codes;

    uint16_t at(int x, int y) const { return codes[static_cast<size_t>(y) * width + x]; }
    uint16_t& at(int x, int y) { return codes[static_cast<size_t>(y) * width + x]; }
};

} // namespace ridge
