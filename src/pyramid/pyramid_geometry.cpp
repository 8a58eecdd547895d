#include "ridge/pyramid/pyramid_geometry.h"

#include "ridge/core/error.h"

#include <algorithm>
#include <string>

namespace ridge {

namespace {

bool isPatchSize(int size)
{
    for (int n = 2; n <= 12; ++n)
        if (size == (1 << n) + 1)
            return true;
    return false;
}

int64_t ceilDiv(int64_t a, int64_t b)
{
    return (a + b - 1) / b;
}

} // namespace

PyramidGeometry::PyramidGeometry(int width, int height, int patch_size)
    : width_(width), height_(height), patch_size_(patch_size)
{
    if (!isPatchSize(patch_size))
        throw Error("patch size " + std::to_string(patch_size) +
                    " is not 2^n+1 with n in [2, 12] (e.g. 65, 129, 257)");
    if (width < 2 || height < 2)
        throw Error("grid " + std::to_string(width) + "x" + std::to_string(height) +
                    " is smaller than 2x2");
    const int64_t extent = std::max(width, height) - 1;
    level_count_ = 1;
    while (int64_t{cells()} << (level_count_ - 1) < extent)
        ++level_count_;
    if (level_count_ > 32)
        throw Error("grid too large for the patch quadtree");
    for (int l = 0; l < level_count_; ++l)
        first_index_[l + 1] = first_index_[l] + patchCount(l);
}

PyramidGeometry PyramidGeometry::fromStored(int width, int height, int patch_size, int level_count)
{
    PyramidGeometry g(width, height, patch_size);
    if (g.levelCount() != level_count)
        throw Error("level count " + std::to_string(level_count) + " does not match a " +
                    std::to_string(width) + "x" + std::to_string(height) + " grid of " +
                    std::to_string(patch_size) + " patches (expected " +
                    std::to_string(g.levelCount()) + ")");
    return g;
}

int PyramidGeometry::levelWidth(int level) const
{
    return static_cast<int>(ceilDiv(width_ - 1, step(level)) + 1);
}

int PyramidGeometry::levelHeight(int level) const
{
    return static_cast<int>(ceilDiv(height_ - 1, step(level)) + 1);
}

int PyramidGeometry::patchesX(int level) const
{
    return static_cast<int>(std::max<int64_t>(1, ceilDiv(levelWidth(level) - 1, cells())));
}

int PyramidGeometry::patchesY(int level) const
{
    return static_cast<int>(std::max<int64_t>(1, ceilDiv(levelHeight(level) - 1, cells())));
}

bool PyramidGeometry::exists(PatchId p) const
{
    return p.level >= 0 && p.level < level_count_ && p.x >= 0 && p.y >= 0 &&
           p.x < patchesX(p.level) && p.y < patchesY(p.level);
}

int64_t PyramidGeometry::patchIndex(PatchId p) const
{
    return first_index_[p.level] + int64_t{p.y} * patchesX(p.level) + p.x;
}

PatchId PyramidGeometry::patchAt(int64_t index) const
{
    int level = 0;
    while (level + 1 < level_count_ && first_index_[level + 1] <= index)
        ++level;
    const int64_t local = index - first_index_[level];
    const int px = patchesX(level);
    return {level, static_cast<int>(local % px), static_cast<int>(local / px)};
}

} // namespace ridge
