// The sample-flags pyramid: coarse levels take the flags of the base sample at their position,
// looked up on demand (docs/FORMAT.md, "Sample flags").
#include "ridge/pyramid/sample_flags.h"

#include "ridge/core/error.h"

#include <algorithm>

namespace ridge {

void PatchSampleFlags::canonicalize()
{
    if (kind != Kind::Mixed)
        return;
    const auto all = [&](uint8_t value) {
        return std::all_of(flags.begin(), flags.end(), [&](uint8_t b) { return b == value; });
    };
    if (all(0))
        kind = Kind::None;
    else if (all(kSampleWater))
        kind = Kind::AllWater;
    if (kind != Kind::Mixed)
        flags.clear();
}

SampleFlagsGrid::SampleFlagsGrid(int width, int height)
    : width_(width), height_(height),
      bits_((static_cast<size_t>(width) * static_cast<size_t>(height) + 3) / 4, 0)
{
}

SampleFlagsGrid::SampleFlagsGrid(const std::vector<uint8_t>& bytes, int width, int height)
    : SampleFlagsGrid(width, height)
{
    if (bytes.size() != static_cast<size_t>(width) * static_cast<size_t>(height))
        throw Error("internal error: sample flags of " + std::to_string(bytes.size()) +
                    " samples for a " + std::to_string(width) + " x " + std::to_string(height) +
                    " grid");
    for (size_t k = 0; k < bytes.size(); ++k)
        bits_[k / 4] |= static_cast<uint8_t>((bytes[k] & kSampleFlagBits) << (2 * (k % 4)));
}

bool SampleFlagsGrid::any() const
{
    return std::any_of(bits_.begin(), bits_.end(), [](uint8_t b) { return b != 0; });
}

SampleFlagsPyramid::SampleFlagsPyramid(SampleFlagsGrid grid, int base_level,
                                       const PyramidGeometry& geometry)
    : geometry_(geometry), base_level_(base_level), grid_(std::move(grid))
{
    if (base_level < 0 || base_level > geometry.finestLevel())
        throw Error("internal error: sample flags of level " + std::to_string(base_level) +
                    " in a pyramid of " + std::to_string(geometry.levelCount()) + " levels");
    if (grid_.width() != geometry.levelWidth(base_level) ||
        grid_.height() != geometry.levelHeight(base_level))
        throw Error("internal error: sample flags of " + std::to_string(grid_.width()) + " x " +
                    std::to_string(grid_.height()) + " samples for level " +
                    std::to_string(base_level) + " of " +
                    std::to_string(geometry.levelWidth(base_level)) + " x " +
                    std::to_string(geometry.levelHeight(base_level)));
    any_ = grid_.any();
}

uint8_t SampleFlagsPyramid::at(int level, int64_t i, int64_t j) const
{
    // Level l's sample i sits at base sample i·2^(base − l); clamping to the base grid gives
    // the finest position min(i·step, W−1) whichever the base (see the class comment).
    const int shift = base_level_ - level;
    const int64_t bi = std::min<int64_t>(std::max<int64_t>(i, 0) << shift, grid_.width() - 1);
    const int64_t bj = std::min<int64_t>(std::max<int64_t>(j, 0) << shift, grid_.height() - 1);
    return grid_.at(bi, bj);
}

PatchSampleFlags SampleFlagsPyramid::patch(PatchId p) const
{
    const int n = geometry_.patchSize(), c = geometry_.cells();
    PatchSampleFlags out;
    out.patch_size = n;
    if (!any_)
        return out;
    out.kind = PatchSampleFlags::Kind::Mixed;
    out.flags.resize(static_cast<size_t>(n) * n);
    const int64_t i0 = int64_t{p.x} * c, j0 = int64_t{p.y} * c;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i)
            out.flags[static_cast<size_t>(j) * n + i] = at(p.level, i0 + i, j0 + j);
    out.canonicalize();
    return out;
}

} // namespace ridge
