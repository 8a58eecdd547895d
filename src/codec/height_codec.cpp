#include "ridge/codec/height_codec.h"

#include "ridge/core/error.h"

#include <cstring>

namespace ridge {

const char* codecStatusMessage(int status)
{
    switch (status) {
    case kCodecOk:
        return "ok";
    case kCodecBadHeader:
        return "bad payload header";
    case kCodecTruncated:
        return "truncated payload";
    case kCodecCorrupt:
        return "corrupt payload";
    case kCodecTrailingBytes:
        return "trailing bytes after payload";
    case kCodecNeedsParent:
        return "patch decoded without its parent's reconstruction";
    case kCodecDisabled:
        return "its decoder is disabled: HTJ2K payloads are decoded only with "
               "RIDGE_ALLOW_HTJ2K=1 (OpenJPH 0.9 aborts the process on some malformed "
               "codestreams; set it for archives you trust)";
    default:
        return "unknown codec error";
    }
}

void HeightCodec::reconstruct(const uint16_t* codes, const PatchContext& ctx, uint16_t* out) const
{
    std::memcpy(out, codes,
                sizeof(uint16_t) * static_cast<size_t>(ctx.patch_size) * ctx.patch_size);
}

void HeightCodec::restoreTraining(const uint8_t* /*data*/, size_t size)
{
    if (size != 0)
        throw Error(std::string("codec '") + name() + "' learns nothing, but a training state of " +
                    std::to_string(size) + " bytes was given");
}

} // namespace ridge
