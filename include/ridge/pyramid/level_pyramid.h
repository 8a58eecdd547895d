#pragma once
// The levels of the multiresolution hierarchy, as read-only views of codes.
//
// Decimation (the hardware-tessellation paper's h^(l-1)(i,j) = h^(l)(2i,2j)) needs no
// storage: level l is a strided view of the finest grid. The Neville-4 filter of the
// JPEG2000 paper (§3.2.1) produces new values, so its coarser levels are materialised
// (1/3 of the finest grid's memory in total).
#include "ridge/core/height_grid.h"
#include "ridge/pyramid/pyramid_geometry.h"

#include <algorithm>
#include <cstdint>
#include <memory>
#include <vector>

namespace ridge {

enum class PyramidFilter : uint32_t {
    Decimate = 0, // h^(l-1)(i,j) = h^(l)(2i,2j)
    Neville4 = 1, // low-pass of the lifting scheme with the 4-point Neville predictor
};

const char* filterName(PyramidFilter filter);
// Parses "decimate" / "neville"; throws ridge::Error otherwise.
PyramidFilter parseFilter(const char* name);

// Level sample (i, j) = source(min(i*step, src_width-1), min(j*step, src_height-1)).
// The clamp is the edge extension that pads every level beyond the valid extent.
struct LevelView {
    const uint16_t* source = nullptr;
    int src_width = 0;
    int src_height = 0;
    int64_t step = 1;
    int width = 0; // samples of this level that cover the valid extent
    int height = 0;

    uint16_t at(int64_t i, int64_t j) const
    {
        const int64_t x = std::min<int64_t>(i * step, src_width - 1);
        const int64_t y = std::min<int64_t>(j * step, src_height - 1);
        return source[y * src_width + x];
    }
};

class LevelPyramid {
  public:
    // `finest` must outlive the pyramid and match geometry's width/height.
    LevelPyramid(const CodeGrid& finest, const PyramidGeometry& geometry, PyramidFilter filter);

    const LevelView& level(int l) const { return levels_[l]; }
    const PyramidGeometry& geometry() const { return geometry_; }
    PyramidFilter filter() const { return filter_; }

  private:
    PyramidGeometry geometry_;
    PyramidFilter filter_;
    std::vector<LevelView> levels_;
    std::vector<std::unique_ptr<CodeGrid>> owned_; // Neville levels
};

// Copies level samples [i0, i0+width) x [j0, j0+height) into out (row-major), edge-extended.
void extractWindow(const LevelView& level, int64_t i0, int64_t j0, int width, int height,
                   uint16_t* out);

// Copies patch (p.level, p.x, p.y) into out[(C+1)^2], row-major, edge-extended.
void extractPatch(const LevelView& level, int patch_size, PatchId p, uint16_t* out);

// One Neville-4 coarsening step: fine (w x h) -> ceil((w-1)/2)+1 x ceil((h-1)/2)+1.
CodeGrid coarsenNeville4(const CodeGrid& fine);

} // namespace ridge
