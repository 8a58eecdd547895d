#pragma once
// Rough synthetic terrain for tests: midpoint displacement (diamond-square) on an n × n grid,
// n = 2^k + 1, with a fixed seed. Uniform numbers come straight from mt19937's bits, which
// the standard pins down (its distributions it does not), so every platform gets the same
// terrain. Header-only: any test executable can use it.
#include <cstdint>
#include <random>
#include <utility>
#include <vector>

namespace ridge::test {

// Row-major heights, metres. Corners at base ± corner_spread; the displacement starts at
// `amplitude` and shrinks by `decay` each halving.
inline std::vector<double> diamondSquare(int n, uint32_t seed, double base, double corner_spread,
                                         double amplitude, double decay)
{
    std::mt19937 rng(seed);
    auto uniform = [&] { return double(rng()) / 4294967296.0 * 2.0 - 1.0; };
    std::vector<double> h(size_t(n) * size_t(n), 0.0);
    auto at = [&](int x, int y) -> double& { return h[size_t(y) * size_t(n) + size_t(x)]; };
    const int c = n - 1;
    at(0, 0) = base + corner_spread * uniform();
    at(c, 0) = base + corner_spread * uniform();
    at(0, c) = base + corner_spread * uniform();
    at(c, c) = base + corner_spread * uniform();
    for (int s = c; s > 1; s /= 2, amplitude *= decay) {
        const int m = s / 2;
        // Diamond step: each square's centre from its four corners.
        for (int y = m; y < n; y += s)
            for (int x = m; x < n; x += s)
                at(x, y) =
                    (at(x - m, y - m) + at(x + m, y - m) + at(x - m, y + m) + at(x + m, y + m)) /
                        4 +
                    amplitude * uniform();
        // Square step: each edge midpoint from its (up to four) neighbours.
        for (int y = 0; y < n; y += m)
            for (int x = (y / m) % 2 == 0 ? m : 0; x < n; x += s) {
                double sum = 0;
                int count = 0;
                for (const auto& [dx, dy] : {std::pair{-m, 0}, {m, 0}, {0, -m}, {0, m}})
                    if (x + dx >= 0 && x + dx < n && y + dy >= 0 && y + dy < n) {
                        sum += at(x + dx, y + dy);
                        ++count;
                    }
                at(x, y) = sum / count + amplitude * uniform();
            }
    }
    return h;
}

} // namespace ridge::test
