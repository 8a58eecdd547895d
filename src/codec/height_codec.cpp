#include "ridge/codec/height_codec.h"

#include "ridge/codec/lossless_codec.h"
#include "ridge/core/error.h"

namespace ridge {

const char* codecStatusMessage(int status)
{
    switch (status) {
    case kCodecOk: return "ok";
    case kCodecBadHeader: return "bad payload header";
    case kCodecTruncated: return "truncated payload";
    case kCodecCorrupt: return "corrupt payload";
    case kCodecTrailingBytes: return "trailing bytes after payload";
    default: return "unknown codec error";
    }
}

std::unique_ptr<HeightCodec> makeCodec(const std::string& name)
{
    if (name == "lossless")
        return std::make_unique<LosslessCodec>();
    if (name == "raw")
        return std::make_unique<Raw16Codec>();
    throw Error("unknown codec '" + name + "' (available: lossless, raw)");
}

std::unique_ptr<HeightCodec> makeCodec(CodecId id)
{
    switch (id) {
    case CodecId::Lossless: return std::make_unique<LosslessCodec>();
    case CodecId::Raw16: return std::make_unique<Raw16Codec>();
    }
    return nullptr;
}

} // namespace ridge
