#include "ridge/codec/height_codec.h"

#include "ridge/codec/lossless_codec.h"
#include "ridge/codec/progressive_codec.h"
#include "ridge/core/error.h"

#include <cmath>
#include <cstring>

namespace ridge {

const char* codecStatusMessage(int status)
{
    switch (status) {
    case kCodecOk: return "ok";
    case kCodecBadHeader: return "bad payload header";
    case kCodecTruncated: return "truncated payload";
    case kCodecCorrupt: return "corrupt payload";
    case kCodecTrailingBytes: return "trailing bytes after payload";
    case kCodecNeedsParent: return "patch decoded without its parent's reconstruction";
    default: return "unknown codec error";
    }
}

void HeightCodec::reconstruct(const uint16_t* codes, const PatchContext& ctx, uint16_t* out) const
{
    std::memcpy(out, codes, sizeof(uint16_t) * static_cast<size_t>(ctx.patch_size) * ctx.patch_size);
}

bool isLossyCodec(const std::string& name)
{
    return name == "progressive" || name == "progressive-paper";
}

std::unique_ptr<HeightCodec> makeCodec(const std::string& name, double max_error, int level_count)
{
    if (name == "lossless")
        return std::make_unique<LosslessCodec>();
    if (name == "raw")
        return std::make_unique<Raw16Codec>();
    if (name == "progressive")
        return std::make_unique<ProgressiveCodec>(max_error, level_count);
    if (name == "progressive-paper")
        return std::make_unique<ProgressiveCodec>(max_error, level_count, ProgressiveVariant::paper());
    throw Error("unknown codec '" + name + "' (available: lossless, raw, progressive, progressive-paper)");
}

std::unique_ptr<HeightCodec> makeCodec(CodecId id, const CodecSettings& settings)
{
    switch (id) {
    case CodecId::Lossless: return std::make_unique<LosslessCodec>();
    case CodecId::Raw16: return std::make_unique<Raw16Codec>();
    case CodecId::Progressive: {
        const double e = settings.param[0], bits = settings.param[1];
        if (!(e >= 0 && e <= 32767 && (bits == 0 || bits == 2 || bits == 4 || bits == 6) &&
              settings.level_count >= 1 && settings.level_count <= 32))
            return nullptr;
        return std::make_unique<ProgressiveCodec>(e, settings.level_count,
                                                  ProgressiveVariant::fromBits(static_cast<int>(bits)));
    }
    }
    return nullptr;
}

} // namespace ridge
