#include "ridge/core/terrain_palette.h"

#include <algorithm>
#include <cmath>

namespace ridge::palette {

namespace {

Rgb mix(Rgb a, Rgb b, float f)
{
    return {a.r + (b.r - a.r) * f, a.g + (b.g - a.g) * f, a.b + (b.b - a.b) * f};
}

} // namespace

template <size_t N> Rgb ramp(const std::array<Stop, N>& stops, float t)
{
    // NaN falls to the first stop rather than through every comparison.
    t = t >= 0.f ? std::min(t, 1.f) : 0.f;
    for (size_t k = 1; k < N; ++k)
        if (t <= stops[k].t)
            return mix(stops[k - 1].colour, stops[k].colour,
                       (t - stops[k - 1].t) / (stops[k].t - stops[k - 1].t));
    return stops[N - 1].colour;
}

template Rgb ramp(const std::array<Stop, kLandStops.size()>&, float);
template Rgb ramp(const std::array<Stop, kWaterStops.size()>&, float);

bool isWater(float metres)
{
    return metres <= 0.f;
}

Rgb terrainColour(float metres, bool water, float min_metres, float max_metres)
{
    if (water)
        return ramp(kWaterStops, min_metres < 0.f ? metres / min_metres : 0.f);
    const float low = std::max(min_metres, 0.f);
    return ramp(kLandStops, (metres - low) / std::max(max_metres - low, 1e-3f));
}

Rgb heat(float t)
{
    auto channel = [](float v) { return std::clamp(v, 0.f, 1.f); };
    return {channel(1.5f - std::abs(4.f * t - 3.f)), channel(1.5f - std::abs(4.f * t - 2.f)),
            channel(1.5f - std::abs(4.f * t - 1.f))};
}

Rgb levelColour(int level)
{
    return kLevelColours[size_t(std::abs(level) % 8)];
}

} // namespace ridge::palette
