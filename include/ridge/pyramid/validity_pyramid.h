#pragma once
// Which samples of each level are data, and which cells a renderer may draw, when the
// source keeps nodata (io::VoidFill). The heights of kept nodata are filled codes, so the
// pyramid and its error bounds run unchanged; this is the mask beside them.
//
// Definitions (normative in docs/FORMAT.md, "Validity mask"):
//  * finest level L: sample valid = the source sample is data.
//  * decimation, level l < L: sample (i, j) is valid iff the finest sample at its position
//    (min(i·step, W−1), min(j·step, H−1)) is, i.e. what `extract` exports at that level.
//  * Neville-4, level l < L: valid iff every level-(l+1) sample of its 9 × 9 filter support
//    (2i + a, 2j + b), a, b in [−4, 4], clamped to the level, is valid: conservatively, no
//    nodata reaches it through the filter.
//  * cell (i, j) of level l (samples (i, j)..(i+1, j+1)) is drawable iff every finest sample
//    of its footprint [i·step, (i+1)·step] × [j·step, (j+1)·step], clipped to the extent, is
//    valid; so no surface is drawn over a finest sample outside the source footprint. Cells
//    wholly past the extent take the last cell's value in that direction (their clipped
//    footprint is part of it).
//  * Patch padding (samples past the level) repeats the clamped sample, as the heights do.
#include "ridge/pyramid/level_pyramid.h"
#include "ridge/pyramid/pyramid_geometry.h"

#include <cstdint>
#include <vector>

namespace ridge {

// One patch's validity. AllValid and NoneValid mean every sample valid and every cell
// drawable, resp. no sample valid and no cell drawable; Mixed holds both bitmaps.
struct PatchValidity {
    enum class Kind : uint8_t { AllValid = 0, NoneValid = 1, Mixed = 2 };
    Kind kind = Kind::AllValid;
    int patch_size = 0;           // n; the bitmaps are n·n samples and (n−1)² cells
    std::vector<uint8_t> samples; // Mixed: n·n, row-major, 1 = valid
    std::vector<uint8_t> cells;   // Mixed: (n−1)·(n−1), row-major, 1 = drawable

    bool sampleValid(int i, int j) const
    {
        return kind == Kind::AllValid ||
               (kind == Kind::Mixed && samples[static_cast<size_t>(j) * patch_size + i] != 0);
    }
    bool cellDrawable(int i, int j) const
    {
        return kind == Kind::AllValid ||
               (kind == Kind::Mixed && cells[static_cast<size_t>(j) * (patch_size - 1) + i] != 0);
    }
    // Sets kind from the bitmaps (AllValid / NoneValid when they are uniform, dropping them).
    void canonicalize();
};

class ValidityPyramid {
  public:
    // `nodata` has one byte per finest sample, non-zero where the sample is not data (as
    // io::ElevationRaster::nodata); it must have geometry.width()·height() entries.
    ValidityPyramid(const std::vector<uint8_t>& nodata, const PyramidGeometry& geometry,
                    PyramidFilter filter);

    // The validity of patch `p` (canonical kind).
    PatchValidity patch(PatchId p) const;
    // Level-sample validity and cell drawability, clamped like the patch padding.
    bool sampleValid(int level, int64_t i, int64_t j) const;
    bool cellDrawable(int level, int64_t i, int64_t j) const;

  private:
    // One bit per sample or cell (1 = valid / drawable): the grids of every level together
    // take 2 · 4/3 bits per finest sample (filled serially: threads would share words).
    struct Grid {
        int width = 0, height = 0;
        std::vector<bool> bits;
        uint8_t at(int64_t i, int64_t j) const
        {
            i = std::clamp<int64_t>(i, 0, width - 1);
            j = std::clamp<int64_t>(j, 0, height - 1);
            return bits[static_cast<size_t>(j) * width + static_cast<size_t>(i)] ? 1 : 0;
        }
    };
    PyramidGeometry geometry_;
    std::vector<Grid> samples_; // per level
    std::vector<Grid> cells_;   // per level
};

} // namespace ridge
