#include "ridge/pyramid/level_pyramid.h"

#include "ridge/core/error.h"

#include <cstring>
#include <string>

namespace ridge {

const char* filterName(PyramidFilter filter)
{
    return filter == PyramidFilter::Neville4 ? "neville" : "decimate";
}

PyramidFilter parseFilter(const char* name)
{
    const std::string s = name;
    if (s == "decimate")
        return PyramidFilter::Decimate;
    if (s == "neville" || s == "neville4")
        return PyramidFilter::Neville4;
    throw Error("unknown filter '" + s + "' (expected decimate or neville)");
}

LevelPyramid::LevelPyramid(const CodeGrid& finest, const PyramidGeometry& geometry,
                           PyramidFilter filter)
    : geometry_(geometry), filter_(filter), levels_(geometry.levelCount())
{
    const int finest_level = geometry.finestLevel();
    if (filter == PyramidFilter::Decimate) {
        for (int l = 0; l <= finest_level; ++l)
            levels_[l] = {finest.codes.data(), finest.width,           finest.height,
                          geometry.step(l),    geometry.levelWidth(l), geometry.levelHeight(l)};
        return;
    }
    // Neville: each level is filtered from the next finer one.
    levels_[finest_level] = {finest.codes.data(), finest.width, finest.height, 1,
                             finest.width,        finest.height};
    const CodeGrid* finer = &finest;
    for (int l = finest_level - 1; l >= 0; --l) {
        owned_.push_back(std::make_unique<CodeGrid>(coarsenNeville4(*finer)));
        finer = owned_.back().get();
        levels_[l] = {finer->codes.data(),    finer->width,           finer->height, 1,
                      geometry.levelWidth(l), geometry.levelHeight(l)};
    }
}

void extractWindow(const LevelView& level, int64_t i0, int64_t j0, int width, int height,
                   uint16_t* out)
{
    // Fast path: a window of a stored grid (finest or Neville level) fully inside it.
    const bool inside =
        level.step == 1 && i0 + width <= level.src_width && j0 + height <= level.src_height;
    for (int v = 0; v < height; ++v) {
        uint16_t* row = out + static_cast<size_t>(v) * width;
        if (inside) {
            std::memcpy(row, level.source + (j0 + v) * level.src_width + i0,
                        sizeof(uint16_t) * width);
            continue;
        }
        for (int u = 0; u < width; ++u)
            row[u] = level.at(i0 + u, j0 + v);
    }
}

void extractPatch(const LevelView& level, int patch_size, PatchId p, uint16_t* out)
{
    const int64_t cells = patch_size - 1;
    extractWindow(level, p.x * cells, p.y * cells, patch_size, patch_size, out);
}

} // namespace ridge
