#include "ridge/stream/bordered_patch.h"

#include <cstddef>

namespace ridge::stream {

std::vector<float> borderedPatch(const uint16_t* codes, int n, const uint16_t* west,
                                 const uint16_t* east, const uint16_t* north, const uint16_t* south)
{
    const int m = n + 2;
    std::vector<float> out(std::size_t(m) * m, 0.f);
    auto at = [&](int i, int j) -> float& { return out[std::size_t(j + 1) * m + (i + 1)]; };
    auto h = [&](int i, int j) { return float(codes[std::size_t(j) * n + i]); };
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i)
            at(i, j) = h(i, j);
    // Neighbours share the border samples: the west neighbour's column n−1 is our column 0,
    // so the sample one step west of ours is its column n−2.
    for (int k = 0; k < n; ++k) {
        at(-1, k) = west ? float(west[std::size_t(k) * n + (n - 2)]) : 2.f * h(0, k) - h(1, k);
        at(n, k) = east ? float(east[std::size_t(k) * n + 1]) : 2.f * h(n - 1, k) - h(n - 2, k);
        at(k, -1) = north ? float(north[std::size_t(n - 2) * n + k]) : 2.f * h(k, 0) - h(k, 1);
        at(k, n) = south ? float(south[std::size_t(1) * n + k]) : 2.f * h(k, n - 1) - h(k, n - 2);
    }
    at(-1, -1) = at(0, -1);
    at(n, -1) = at(n - 1, -1);
    at(-1, n) = at(0, n);
    at(n, n) = at(n - 1, n);
    return out;
}

} // namespace ridge::stream
