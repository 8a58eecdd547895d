#pragma once
// Geometry of the patch quadtree ("Patch Quad Tree", Yusov & Shevtsov 2011, §4).
//
// Level L (finest) is the input grid; level l has sample spacing step(l) = 2^(L-l) finest
// samples, and level 0 is a single patch of (C+1)^2 samples, C = patch_size - 1 = 2^n.
// L is the smallest level count with C * 2^L >= max(width, height) - 1.
//
// Only patches whose footprint touches the valid extent exist. Because the valid extent
// starts at sample (0, 0), the existing patches of a level always form a rectangle
// patchesX(l) x patchesY(l), so an index position is a pure function of (level, x, y).
#include <algorithm>
#include <cstdint>

namespace ridge {

struct PatchId {
    int level = 0;
    int x = 0;
    int y = 0;
    bool operator==(const PatchId&) const = default;

    // The patch one level coarser that covers this one (level > 0).
    PatchId parent() const { return {level - 1, x / 2, y / 2}; }
    // This patch's quadrant in its parent: (x & 1) | (y & 1) << 1 (PatchContext::child_index).
    int childIndex() const { return (x & 1) | ((y & 1) << 1); }
};

class PyramidGeometry {
  public:
    PyramidGeometry() = default;
    // Throws ridge::Error when patch_size is not 2^n + 1 with n in [2, 12] or the grid is
    // smaller than 2x2.
    PyramidGeometry(int width, int height, int patch_size);
    // Rebuilds a geometry from stored fields; throws ridge::Error when they are inconsistent.
    static PyramidGeometry fromStored(int width, int height, int patch_size, int level_count);

    int width() const { return width_; }
    int height() const { return height_; }
    int patchSize() const { return patch_size_; }
    int cells() const { return patch_size_ - 1; }
    int levelCount() const { return level_count_; }
    int finestLevel() const { return level_count_ - 1; }

    // Finest-grid samples between two neighbouring samples of `level`.
    int64_t step(int level) const { return int64_t{1} << (finestLevel() - level); }
    // Samples of `level` needed to cover the valid extent: ceil((width-1)/step) + 1.
    int levelWidth(int level) const;
    int levelHeight(int level) const;
    // Samples of `level` that lie inside the valid extent: floor((width-1)/step) + 1.
    int validLevelWidth(int level) const
    {
        return static_cast<int>((width_ - 1) / step(level) + 1);
    }
    int validLevelHeight(int level) const
    {
        return static_cast<int>((height_ - 1) / step(level) + 1);
    }
    // How far patch `p`'s surface reaches along x (y), in its level's cells from its west
    // (north) border: cells() for a patch that ends inside the valid extent, less for one that
    // reaches past the east (south) border, whose surface must end exactly on the last finest
    // column W − 1 (row H − 1). That is a fraction of a cell when step does not divide W − 1:
    // the level's last sample inside the extent stops short by up to step − 1 finest samples,
    // and the surface continues towards the next (edge-extended) sample, cut at W − 1. Exact
    // in double: step is a power of two.
    double validExtentX(PatchId p) const
    {
        return std::clamp(double(width_ - 1) / double(step(p.level)) - double(p.x) * cells(), 0.0,
                          double(cells()));
    }
    double validExtentY(PatchId p) const
    {
        return std::clamp(double(height_ - 1) / double(step(p.level)) - double(p.y) * cells(), 0.0,
                          double(cells()));
    }
    // Cells of `p` that surface takes samples from: ceil(validExtentX), up to the first sample
    // at or beyond the border (levelWidth − 1). Err_Int and λ count those samples, padding
    // included (pyramid/patch_error.h), so the bounds hold for the surface up to the border.
    int coveredCellsX(PatchId p) const
    {
        return std::clamp(levelWidth(p.level) - 1 - p.x * cells(), 0, cells());
    }
    int coveredCellsY(PatchId p) const
    {
        return std::clamp(levelHeight(p.level) - 1 - p.y * cells(), 0, cells());
    }
    // Whether `p` lies wholly inside the valid extent (nothing of it to clip).
    bool whole(PatchId p) const { return validExtentX(p) >= cells() && validExtentY(p) >= cells(); }
    int patchesX(int level) const;
    int patchesY(int level) const;
    int64_t patchCount(int level) const { return int64_t{patchesX(level)} * patchesY(level); }
    int64_t patchCount() const { return first_index_[level_count_]; }
    bool exists(PatchId p) const;

    // Position of a patch in the archive index: levels coarse to fine, rows, columns.
    int64_t patchIndex(PatchId p) const;
    PatchId patchAt(int64_t index) const;
    int64_t firstPatchIndex(int level) const { return first_index_[level]; }

  private:
    int width_ = 0;
    int height_ = 0;
    int patch_size_ = 0;
    int level_count_ = 0;
    int64_t first_index_[33] = {};
};

} // namespace ridge
