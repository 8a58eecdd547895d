#include "ridge/archive/sample_flags_storage.h"

#include "bitmap_frame.h"
#include "context_bitmap.h"

#include "ridge/archive/format.h"

#include <algorithm>

namespace ridge::archive {

namespace {

constexpr uint8_t kKindNone = 0, kKindAllWater = 1, kKindBitmap = 2, kKindContextBitmap = 3;
// Kind 3's plane byte: which bitmaps are coded (an absent one is all 0).
constexpr uint8_t kPlaneWater = 1, kPlaneFilled = 2;

bool anySet(const std::vector<uint8_t>& plane)
{
    return std::any_of(plane.begin(), plane.end(), [](uint8_t b) { return b != 0; });
}

// Kind 3: the plane byte, u32 stream_size, then the context-coded planes (context_bitmap.h).
std::vector<uint8_t> packContextBitmap(const std::vector<uint8_t>& water,
                                       const std::vector<uint8_t>& filled, int n)
{
    const uint8_t present =
        uint8_t((anySet(water) ? kPlaneWater : 0) | (anySet(filled) ? kPlaneFilled : 0));
    std::vector<const std::vector<uint8_t>*> planes;
    if (present & kPlaneWater)
        planes.push_back(&water);
    if (present & kPlaneFilled)
        planes.push_back(&filled);
    const std::vector<uint8_t> stream = detail::encodeContextBitmap(planes, n);
    std::vector<uint8_t> out{kKindContextBitmap, present};
    for (int k = 0; k < 4; ++k)
        out.push_back(static_cast<uint8_t>(stream.size() >> (8 * k)));
    out.insert(out.end(), stream.begin(), stream.end());
    return out;
}

std::string unpackContextBitmap(const uint8_t* data, size_t size, int n,
                                std::vector<uint8_t>& water, std::vector<uint8_t>& filled,
                                size_t& consumed)
{
    if (size < 6)
        return "sample flags kind 3 truncated before its stream size";
    const uint8_t present = data[1];
    if (present == 0 || (present & ~(kPlaneWater | kPlaneFilled)))
        return "sample flags kind 3 plane byte is " + std::to_string(present) +
               ": must be 1 (water), 2 (filled) or 3 (both)";
    const uint32_t stream_size = uint32_t(data[2]) | uint32_t(data[3]) << 8 |
                                 uint32_t(data[4]) << 16 | uint32_t(data[5]) << 24;
    if (stream_size > size - 6)
        return "sample flags kind 3 stream of " + std::to_string(stream_size) +
               " bytes runs past the blob's " + std::to_string(size - 6);
    std::vector<std::vector<uint8_t>*> planes;
    if (present & kPlaneWater)
        planes.push_back(&water);
    if (present & kPlaneFilled)
        planes.push_back(&filled);
    if (!detail::decodeContextBitmap(data + 6, stream_size, n, planes))
        return "sample flags kind 3 stream is corrupt (it does not code exactly " +
               std::to_string(planes.size()) + " planes of n² bits in its " +
               std::to_string(stream_size) + " bytes)";
    for (const auto* plane : planes) {
        if (!anySet(*plane))
            return std::string("sample flags kind 3 codes an empty ") +
                   (plane == &water ? "water" : "filled") +
                   " plane (not canonical: leave it out of the plane byte)";
    }
    consumed = 6 + size_t(stream_size);
    return {};
}

} // namespace

std::vector<uint8_t> packSampleFlags(const PatchSampleFlags& flags, int patch_size,
                                     uint32_t version)
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
    if (version >= kFirstVersionWithContextCodedFlags)
        return packContextBitmap(water, filled, patch_size);
    return detail::packBitmapFrame(kKindBitmap, {&water, &filled});
}

std::string unpackSampleFlags(const uint8_t* data, size_t size, int patch_size,
                              const PatchValidity* validity, PatchSampleFlags& out,
                              size_t& consumed, uint32_t version)
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
    } else if (kind == kKindBitmap || kind == kKindContextBitmap) {
        // One kind of bitmap per version, so that every patch has exactly one encoding.
        const bool context_coded = version >= kFirstVersionWithContextCodedFlags;
        if ((kind == kKindContextBitmap) != context_coded)
            return "sample flags kind is " + std::to_string(kind) + ": format version " +
                   std::to_string(version) + " codes bitmaps as kind " +
                   (context_coded ? "3 (context-coded)" : "2 (zstd)");
        const size_t samples = static_cast<size_t>(n) * n;
        std::vector<uint8_t> water(samples), filled(samples);
        size_t frame_bytes = 0;
        const std::string problem =
            context_coded ? unpackContextBitmap(data, size, n, water, filled, frame_bytes)
                          : detail::unpackBitmapFrame(data, size, "sample flags", "ceil(2·n² / 8)",
                                                      {&water, &filled}, frame_bytes);
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
               ": must be 0 (none), 1 (all water) or " +
               (version >= kFirstVersionWithContextCodedFlags ? "3 (context-coded bitmaps)"
                                                              : "2 (bitmaps)");
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
