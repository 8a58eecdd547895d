// Border-connected voids: a flood fill (8-connected) seeded at every void on the border.
// 8-connectivity because a collar that narrows to a diagonal step (a warped raster's
// staircase edge) is still one region outside the survey.
#include "border_voids.h"

#include <cstddef>

namespace ridge::io::detail {

std::vector<uint8_t> borderConnectedVoids(const std::vector<uint8_t>& void_mask, int width,
                                          int height, int64_t& kept)
{
    const size_t count = static_cast<size_t>(width) * height;
    std::vector<uint8_t> out(count, 0);
    kept = 0;
    if (void_mask.size() != count)
        return out; // no voids recorded
    std::vector<int64_t> stack;
    auto seed = [&](int x, int y) {
        const size_t i = static_cast<size_t>(y) * width + x;
        if (void_mask[i] == 0 && out[i] == 0) {
            out[i] = 1;
            ++kept;
            stack.push_back(static_cast<int64_t>(i));
        }
    };
    for (int x = 0; x < width; ++x) {
        seed(x, 0);
        seed(x, height - 1);
    }
    for (int y = 0; y < height; ++y) {
        seed(0, y);
        seed(width - 1, y);
    }
    while (!stack.empty()) {
        const int64_t i = stack.back();
        stack.pop_back();
        const int x = static_cast<int>(i % width), y = static_cast<int>(i / width);
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                const int nx = x + dx, ny = y + dy;
                if ((dx || dy) && nx >= 0 && ny >= 0 && nx < width && ny < height)
                    seed(nx, ny);
            }
    }
    return out;
}

} // namespace ridge::io::detail
