#pragma once
// Per-sample attributes that a height cannot carry (docs/FORMAT.md, "Sample flags", format
// version 4): whether a sample is water, and whether its height was invented by void filling.
//
// Why not from the heights: water used to be "height <= 0 m", which a lossy archive breaks
// (a 0 m sea decoded within a 1 m bound is +1 m: land), and which no height can decide for a
// lake or for land below sea level. The build decides it once, from the source's exact values
// (`--sea-level`) and any water layer (`--water FILE`), and stores it beside the heights.
//
// Definitions (normative in docs/FORMAT.md):
//  * finest level L: the build's decision per source sample; a sample that is not valid
//    (kept nodata) has no flag.
//  * level l < L, either filter: the flags of the finest sample at the position,
//    (min(i·step, W−1), min(j·step, H−1)) — a classification is not filtered. Patch padding
//    repeats the clamped sample, as the heights do.
#include "ridge/core/sample_flag_bits.h"
#include "ridge/pyramid/pyramid_geometry.h"

#include <cstdint>
#include <vector>

namespace ridge {

// One patch's flags. None: no sample has a flag; AllWater: every sample is water and none
// was filled; Mixed: `flags` holds n·n bytes, row-major (the bits above).
struct PatchSampleFlags {
    enum class Kind : uint8_t { None = 0, AllWater = 1, Mixed = 2 };
    Kind kind = Kind::None;
    int patch_size = 0;
    std::vector<uint8_t> flags;

    uint8_t at(int i, int j) const
    {
        switch (kind) {
        case Kind::None:
            return 0;
        case Kind::AllWater:
            return kSampleWater;
        case Kind::Mixed:
            break;
        }
        return flags[static_cast<size_t>(j) * patch_size + i];
    }
    bool water(int i, int j) const { return (at(i, j) & kSampleWater) != 0; }
    bool filled(int i, int j) const { return (at(i, j) & kSampleFilled) != 0; }
    // Sets kind from the bytes (None / AllWater when they are uniform, dropping them).
    void canonicalize();
};

// A grid of sample flags at 2 bits a sample (a quarter of a byte: a streamed build holds one
// for level L−1 of a planet-sized raster).
class SampleFlagsGrid {
  public:
    SampleFlagsGrid() = default;
    SampleFlagsGrid(int width, int height); // every sample 0
    // From one byte a sample, row-major (width·height bytes; throws Error for another size).
    SampleFlagsGrid(const std::vector<uint8_t>& bytes, int width, int height);

    int width() const { return width_; }
    int height() const { return height_; }
    // (i, j) inside the grid; flags within kSampleFlagBits.
    void set(int64_t i, int64_t j, uint8_t flags)
    {
        const size_t k = index(i, j);
        bits_[k / 4] = static_cast<uint8_t>((bits_[k / 4] & ~(3u << (2 * (k % 4)))) |
                                            ((flags & kSampleFlagBits) << (2 * (k % 4))));
    }
    uint8_t at(int64_t i, int64_t j) const
    {
        const size_t k = index(i, j);
        return static_cast<uint8_t>((bits_[k / 4] >> (2 * (k % 4))) & 3u);
    }
    bool any() const;

  private:
    size_t index(int64_t i, int64_t j) const
    {
        return static_cast<size_t>(j) * static_cast<size_t>(width_) + static_cast<size_t>(i);
    }
    int width_ = 0, height_ = 0;
    std::vector<uint8_t> bits_;
};

// The flags of every level from one grid of flags at a base level: the finest level, or
// level L−1 of a streamed build, which holds the finest samples at even positions (a level-l
// sample's position is the same finest sample either way: positions clamp to the extent).
// Memory: the base grid's quarter byte a sample; coarser levels are lookups, never stored.
class SampleFlagsPyramid {
  public:
    // `grid` is the grid of `base_level`: geometry.levelWidth(base_level) ×
    // levelHeight(base_level) samples (throws Error for another size).
    SampleFlagsPyramid(SampleFlagsGrid grid, int base_level, const PyramidGeometry& geometry);

    // Flags of level sample (i, j), clamped like the patch padding; level <= base level.
    uint8_t at(int level, int64_t i, int64_t j) const;
    // The flags of patch `p` (canonical kind); p.level <= base level.
    PatchSampleFlags patch(PatchId p) const;
    // Whether any sample has a flag (false: every patch is kind None).
    bool any() const { return any_; }

  private:
    PyramidGeometry geometry_;
    int base_level_ = 0;
    SampleFlagsGrid grid_;
    bool any_ = false;
};

} // namespace ridge
