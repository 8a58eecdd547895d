#include "ridge/archive/sample_flags_storage.h"

#include "bitmap_frame.h"

namespace ridge::archive {

namespace {

constexpr uint8_t kKindNone = 0, kKindAllWater = 1, kKindBitmap = 2;

} // namespace

std::vector<uint8_t> packSampleFlags(const PatchSampleFlags& flags, int patch_size)
{
    PatchSampleFlags f = flags;
    f.canonicalize();
    if (f.kind == PatchSampleFlags::Kind::None)
        return {kKindNone};
    if (f.kind == PatchSampleFlags::Kind::AllWater)
        return {kKindAllWater};
    const size_t samples = static_cast<size_t>(patch_size) * patch_size;
    if (f.flags.size() != samples)
        return {};
    std::vector<uint8_t> water(samples), filled(samples);
    for (size_t k = 0; k < samples; ++k) {
        water[k] = f.flags[k] & kSampleWater;
        filled[k] = f.flags[k] & kSampleFilled;
    }
    return detail::packBitmapFrame(kKindBitmap, {&water, &filled});
}

std::string unpackSampleFlags(const uint8_t* data, size_t size, int patch_size,
                              const PatchValidity* validity, PatchSampleFlags& out,
                              size_t& consumed)
{
    const int n = patch_size;
    out = PatchSampleFlags{};
    out.patch_size = n;
    consumed = 0;
    if (size < 1)
        return "sample flags missing (blob ends after its validity mask)";
    const uint8_t kind = data[0];
    if (kind == kKindNone || kind == kKindAllWater) {
        out.kind =
            kind == kKindNone ? PatchSampleFlags::Kind::None : PatchSampleFlags::Kind::AllWater;
        consumed = 1;
    } else if (kind == kKindBitmap) {
        const size_t samples = static_cast<size_t>(n) * n;
        std::vector<uint8_t> water(samples), filled(samples);
        size_t frame_bytes = 0;
        const std::string problem = detail::unpackBitmapFrame(
            data, size, "sample flags", "ceil(2·n² / 8)", {&water, &filled}, frame_bytes);
        if (!problem.empty())
            return problem;
        out.kind = PatchSampleFlags::Kind::Mixed;
        out.flags.resize(samples);
        for (size_t k = 0; k < samples; ++k)
            out.flags[k] = static_cast<uint8_t>((water[k] ? kSampleWater : 0) |
                                                (filled[k] ? kSampleFilled : 0));
        PatchSampleFlags canonical = out;
        canonical.canonicalize();
        if (canonical.kind != PatchSampleFlags::Kind::Mixed)
            return std::string("sample flags bitmap is uniform (") +
                   (canonical.kind == PatchSampleFlags::Kind::None ? "no flag" : "all water") +
                   "): must be stored as kind " +
                   (canonical.kind == PatchSampleFlags::Kind::None ? "0" : "1");
        consumed = frame_bytes;
    } else {
        return "sample flags kind is " + std::to_string(kind) +
               ": must be 0 (none), 1 (all water) or 2 (bitmaps)";
    }
    if (validity && validity->kind != PatchValidity::Kind::AllValid &&
        out.kind != PatchSampleFlags::Kind::None)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i)
                if (out.at(i, j) != 0 && !validity->sampleValid(i, j)) {
                    consumed = 0;
                    return "sample flags: sample (" + std::to_string(i) + ", " + std::to_string(j) +
                           ") is flagged " + (out.water(i, j) ? "water" : "filled") +
                           " but is not valid (nodata has no flags)";
                }
    return {};
}

} // namespace ridge::archive
