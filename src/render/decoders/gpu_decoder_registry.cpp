// The GPU decoders, one line each: a codec's GPU half is its module under src/render/decoders/
// and its line here (gpu_patch_decoder.h).
#include "gpu_patch_decoder.h"

#include <cstring>
#include <vector>

namespace ridge::render {

GpuDecoderInfo progressiveGpuDecoder();
GpuDecoderInfo jpeg2000GpuDecoder();
GpuDecoderInfo fractalGpuDecoder();

namespace {

const std::vector<GpuDecoderInfo>& registry()
{
    // clang-format off
    static const std::vector<GpuDecoderInfo> decoders = {
        progressiveGpuDecoder(),
        jpeg2000GpuDecoder(),
        fractalGpuDecoder(),
    };
    // clang-format on
    return decoders;
}

} // namespace

const GpuDecoderInfo* findGpuDecoder(const HeightCodec& codec)
{
    for (const GpuDecoderInfo& d : registry())
        if (std::strcmp(d.codec, codec.name()) == 0)
            return &d;
    return nullptr;
}

} // namespace ridge::render
