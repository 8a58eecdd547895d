#include "ridge/lod/clipmap.h"

#include "ridge/core/error.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace ridge::lod {
namespace {

// The largest multiple of b (> 0) at or below a.
int64_t floorTo(int64_t a, int64_t b)
{
    return floorDiv(a, b) * b;
}

// The samples of `now` that `before` (the same size) does not hold: the L-shaped strip as
// at most two disjoint rectangles (a full-height column band, then the rest of a row band).
std::vector<LevelRect> newSamples(const LevelRect& before, const LevelRect& now)
{
    const int64_t size = now.x1 - now.x0;
    const int64_t dx = now.x0 - before.x0, dy = now.y0 - before.y0;
    if (std::abs(dx) >= size || std::abs(dy) >= size)
        return {now};
    std::vector<LevelRect> out;
    int64_t kept_x0 = now.x0, kept_x1 = now.x1; // columns also in `before`
    if (dx > 0) {
        out.push_back({before.x1, now.y0, now.x1, now.y1});
        kept_x1 = before.x1;
    } else if (dx < 0) {
        out.push_back({now.x0, now.y0, before.x0, now.y1});
        kept_x0 = before.x0;
    }
    if (dy > 0)
        out.push_back({kept_x0, before.y1, kept_x1, now.y1});
    else if (dy < 0)
        out.push_back({kept_x0, now.y0, kept_x1, before.y0});
    return out;
}

} // namespace

void ClipmapSettings::validate() const
{
    const bool power = n >= kMinN && n <= kMaxN && ((n + 1) & n) == 0;
    if (!power)
        throw Error("clipmaps: n " + std::to_string(n) + " must be 2^k − 1 between " +
                    std::to_string(kMinN) + " and " + std::to_string(kMaxN) +
                    " (63, 127, 255, 511 or 1023)");
    if (levels < 0 || levels > kMaxLevels)
        throw Error("clipmaps: levels " + std::to_string(levels) + " must be 0 (as the terrain " +
                    "needs) to " + std::to_string(kMaxLevels));
}

int clipmapLevelCount(const ClipmapSettings& settings, const PyramidGeometry& geometry)
{
    settings.validate();
    if (settings.levels > 0)
        return settings.levels;
    // The coarsest window must reach the far border from a viewer on the near one: its half
    // width less the 1.5 cells a window may sit off the viewer, at least the terrain's extent.
    const int64_t extent = std::max(geometry.width(), geometry.height()) - 1;
    const int64_t reach = (settings.n - 1) / 2 - 2;
    int levels = 1;
    for (int64_t step = 1; reach * step < extent && levels < ClipmapSettings::kMaxLevels; step *= 2)
        ++levels;
    // And down to the archive's level 0 at least: the root is always resident, so the
    // coarsest level can always be drawn while the others wait for their patches.
    return std::clamp(geometry.levelCount(), levels, ClipmapSettings::kMaxLevels);
}

int64_t floorDiv(int64_t a, int64_t b)
{
    return a >= 0 ? a / b : -((b - 1 - a) / b);
}

int transitionWidth(int n)
{
    return std::max(2, (n + 1) / 10);
}

double transitionAlpha(int n, double distance)
{
    const double w = transitionWidth(n);
    return std::clamp((distance - ((n - 1) / 2 - w - 2)) / w, 0.0, 1.0);
}

ClipmapWindows::ClipmapWindows(const PyramidGeometry& geometry, const ClipmapSettings& settings)
    : n_(settings.n), finest_(geometry.finestLevel())
{
    const int L = clipmapLevelCount(settings, geometry);
    levels_.resize(size_t(L));
    updates_.resize(size_t(L));
    for (int k = 0; k < L; ++k) {
        ClipmapLevel& level = levels_[size_t(k)];
        level.pyramid_level = int(finest_) - (L - 1 - k);
        level.step = int64_t{1} << (L - 1 - k);
    }
}

int ClipmapWindows::place(double centre_x, double centre_y)
{
    if (!std::isfinite(centre_x) || !std::isfinite(centre_y) || std::abs(centre_x) > 1e15 ||
        std::abs(centre_y) > 1e15)
        throw Error("clipmaps: the window centre must be finite grid coordinates");
    const int L = levelCount();
    const int64_t half = (n_ - 1) / 2, m = (n_ + 1) / 4;
    std::vector<ClipmapLevel> next = levels_;
    // The finest: centred on the viewer, rounded to the nearest even sample of its level (so
    // that it lies on the coarser grid).
    ClipmapLevel& finest = next[size_t(L - 1)];
    const int64_t s = finest.step;
    finest.origin_x =
        2 * s * int64_t(std::floor((centre_x / double(s) - double(half)) / 2.0 + 0.5));
    finest.origin_y =
        2 * s * int64_t(std::floor((centre_y / double(s) - double(half)) / 2.0 + 0.5));
    // Each coarser one: m − 1 of its cells before the finer origin, down to its own coarser
    // grid; the finer one then sits 0 or 1 cell into the 2m-cell hole.
    for (int k = L - 2; k >= 0; --k) {
        ClipmapLevel& coarse = next[size_t(k)];
        const ClipmapLevel& fine = next[size_t(k + 1)];
        const int64_t S = coarse.step;
        coarse.origin_x = floorTo(fine.origin_x - (m - 1) * S, 2 * S);
        coarse.origin_y = floorTo(fine.origin_y - (m - 1) * S, 2 * S);
        coarse.finer_x = int((fine.origin_x - coarse.origin_x) / S - (m - 1));
        coarse.finer_y = int((fine.origin_y - coarse.origin_y) / S - (m - 1));
    }
    int shifted = 0;
    for (int k = 0; k < L; ++k) {
        const ClipmapLevel& before = levels_[size_t(k)];
        const ClipmapLevel& now = next[size_t(k)];
        std::vector<LevelRect>& updates = updates_[size_t(k)];
        updates.clear();
        if (!placed_) {
            updates.push_back(now.window(n_));
            ++shifted;
        } else if (now.origin_x != before.origin_x || now.origin_y != before.origin_y) {
            updates = newSamples(before.window(n_), now.window(n_));
            ++shifted;
        }
    }
    levels_ = std::move(next);
    placed_ = true;
    return shifted;
}

int finestDrawnLevel(const ClipmapWindows& windows, double spacing, double height,
                     double fov_y_radians, int viewport_height_px)
{
    const double h = std::max(height, 0.0);
    const double pixel = h * std::tan(fov_y_radians / std::max(viewport_height_px, 1));
    for (int k = windows.levelCount() - 1; k > 0; --k) {
        const double cell = spacing * double(windows.level(k).step);
        if (cell >= 2.0 * pixel)
            return k;
    }
    return 0;
}

} // namespace ridge::lod
