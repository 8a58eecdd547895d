#include "ridge/codec/height_codec.h"

#include "ridge/codec/lossless_codec.h"
#include "ridge/codec/progressive_codec.h"
#include "ridge/core/error.h"
#include "ridge/core/parameter_check.h"

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

std::optional<CodecId> codecIdOf(const std::string& name)
{
    if (name == "raw")
        return CodecId::Raw16;
    if (name == "lossless")
        return CodecId::Lossless;
    if (name == "progressive" || name == "progressive-paper")
        return CodecId::Progressive;
    return std::nullopt;
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

namespace {

// What makeCodec(CodecId, ...) returns for settings it cannot accept.
std::unique_ptr<HeightCodec> rejected(std::string* problem, std::string text)
{
    if (problem)
        *problem = std::move(text);
    return nullptr;
}

// Raw and lossless codecs have no parameters: both stored values must be exactly 0, so that a
// future parameter of theirs cannot be silently ignored by this reader.
std::string checkNoParameters(const char* codec, const CodecSettings& s)
{
    for (int k = 0; k < 2; ++k)
        if (!(s.param[k] == 0))
            return "codec_param[" + std::to_string(k) + "] is " + formatNumber(s.param[k]) +
                   ": the " + codec + " codec takes no parameters (must be 0)";
    return {};
}

// The progressive codec: param[0] = δ_l0 in codes (real), param[1] = variant bits (bit 1
// cubic prediction, bit 2 activity contexts, nothing else), at most 32 levels
// (LevelQuantizer shifts by up to 30).
std::string checkProgressiveParameters(const CodecSettings& s)
{
    constexpr ValueRange kMaxErrorCodes = ValueRange::closed(0, 32767);
    if (!kMaxErrorCodes.contains(s.param[0]))
        return "codec_param[0] is " + formatNumber(s.param[0]) +
               ": the progressive codec's finest-level bound δ_l0 (codes) must be " +
               kMaxErrorCodes.describe();
    const double bits = s.param[1];
    if (!(bits == 0 || bits == 2 || bits == 4 || bits == 6))
        return "codec_param[1] is " + formatNumber(bits) +
               ": the progressive codec's variant must be 0, 2, 4 or 6 (bit 1 cubic prediction, "
               "bit 2 activity contexts)";
    if (s.level_count < 1 || s.level_count > 32)
        return "level_count is " + std::to_string(s.level_count) +
               ": the progressive codec codes 1 to 32 levels";
    return {};
}

} // namespace

std::unique_ptr<HeightCodec> makeCodec(CodecId id, const CodecSettings& settings,
                                       std::string* problem)
{
    switch (id) {
    case CodecId::Raw16:
        if (std::string p = checkNoParameters("raw", settings); !p.empty())
            return rejected(problem, std::move(p));
        return std::make_unique<Raw16Codec>();
    case CodecId::Lossless:
        if (std::string p = checkNoParameters("lossless", settings); !p.empty())
            return rejected(problem, std::move(p));
        return std::make_unique<LosslessCodec>();
    case CodecId::Progressive: {
        if (std::string p = checkProgressiveParameters(settings); !p.empty())
            return rejected(problem, std::move(p));
        return std::make_unique<ProgressiveCodec>(
            settings.param[0], settings.level_count,
            ProgressiveVariant::fromBits(static_cast<int>(settings.param[1])));
    }
    }
    return rejected(problem, "codec_id is " + std::to_string(static_cast<uint32_t>(id)) +
                                 ": must be 0 (raw), 1 (lossless) or 2 (progressive)");
}

} // namespace ridge
