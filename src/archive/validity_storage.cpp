#include "ridge/archive/validity_storage.h"

#include "bitmap_frame.h"

namespace ridge::archive {

namespace {

constexpr uint8_t kKindAll = 0, kKindNone = 1, kKindBitmap = 2;

} // namespace

std::vector<uint8_t> packValidity(const PatchValidity& validity, int patch_size)
{
    PatchValidity v = validity;
    v.canonicalize();
    if (v.kind == PatchValidity::Kind::AllValid)
        return {kKindAll};
    if (v.kind == PatchValidity::Kind::NoneValid)
        return {kKindNone};
    if (v.samples.size() != static_cast<size_t>(patch_size) * patch_size ||
        v.cells.size() != static_cast<size_t>(patch_size - 1) * (patch_size - 1))
        return {};
    return detail::packBitmapFrame(kKindBitmap, {&v.samples, &v.cells});
}

std::string unpackValidity(const uint8_t* data, size_t size, int patch_size, bool corners_rule,
                           PatchValidity& out, size_t& consumed)
{
    const int n = patch_size, c = n - 1;
    out = PatchValidity{};
    out.patch_size = n;
    consumed = 0;
    if (size < 1)
        return "validity mask missing (blob ends after its block errors)";
    if (data[0] == kKindAll || data[0] == kKindNone) {
        out.kind =
            data[0] == kKindAll ? PatchValidity::Kind::AllValid : PatchValidity::Kind::NoneValid;
        consumed = 1;
        return {};
    }
    if (data[0] != kKindBitmap)
        return "validity kind is " + std::to_string(data[0]) +
               ": must be 0 (all valid), 1 (none valid) or 2 (bitmap)";
    out.kind = PatchValidity::Kind::Mixed;
    out.samples.resize(static_cast<size_t>(n) * n);
    out.cells.resize(static_cast<size_t>(c) * c);
    size_t frame_bytes = 0;
    const std::string problem = detail::unpackBitmapFrame(
        data, size, "validity", "ceil((n² + (n−1)²) / 8)", {&out.samples, &out.cells}, frame_bytes);
    if (!problem.empty())
        return problem;
    PatchValidity canonical = out;
    canonical.canonicalize();
    if (canonical.kind != PatchValidity::Kind::Mixed)
        return std::string("validity bitmap is uniform (") +
               (canonical.kind == PatchValidity::Kind::AllValid ? "all valid" : "none valid") +
               "): must be stored as kind " +
               (canonical.kind == PatchValidity::Kind::AllValid ? "0" : "1");
    if (corners_rule)
        for (int j = 0; j < c; ++j)
            for (int i = 0; i < c; ++i)
                if (out.cellDrawable(i, j) &&
                    !(out.sampleValid(i, j) && out.sampleValid(i + 1, j) &&
                      out.sampleValid(i, j + 1) && out.sampleValid(i + 1, j + 1)))
                    return "validity cell (" + std::to_string(i) + ", " + std::to_string(j) +
                           ") is drawable but a corner sample is not valid";
    consumed = frame_bytes;
    return {};
}

} // namespace ridge::archive
