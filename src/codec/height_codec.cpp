#include "ridge/codec/height_codec.h"

#include "ridge/codec/jpeg2000_codec.h"
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

namespace {

constexpr const char* kCodecList =
    "lossless, raw, progressive, progressive-v1, progressive-paper, jpeg2000";

// A progressive variant by name: "progressive" (v2), "progressive-v1", "progressive-paper",
// and v2 with options for measurement, "progressive,nested=K". Null for anything else.
std::optional<ProgressiveVariant> progressiveVariantOf(const std::string& name)
{
    if (name == "progressive")
        return ProgressiveVariant{};
    if (name == "progressive-v1")
        return ProgressiveVariant::v1();
    if (name == "progressive-paper")
        return ProgressiveVariant::paper();
    // "progressive,OPTION,..." with nested=K (1..32) and corrections=0|1.
    const std::string prefix = "progressive,";
    if (name.rfind(prefix, 0) != 0)
        return std::nullopt;
    ProgressiveVariant v;
    size_t at = prefix.size();
    while (at <= name.size()) {
        const size_t comma = std::min(name.find(',', at), name.size());
        const std::string option = name.substr(at, comma - at);
        const size_t eq = option.find('=');
        if (eq == std::string::npos)
            return std::nullopt;
        const std::string key = option.substr(0, eq), value = option.substr(eq + 1);
        if (value.empty() || value.size() > 2 ||
            value.find_first_not_of("0123456789") != std::string::npos)
            return std::nullopt;
        const int number = std::stoi(value);
        if (key == "nested" && number >= 1 && number <= 32)
            v.nested_levels = number;
        else if (key == "corrections" && number <= 1)
            v.corrections = number == 1;
        else
            return std::nullopt;
        at = comma + 1;
    }
    return v;
}

} // namespace

bool isLossyCodec(const std::string& name)
{
    return progressiveVariantOf(name).has_value() || Jpeg2000Variant::fromName(name).has_value();
}

std::optional<CodecId> codecIdOf(const std::string& name)
{
    if (name == "raw")
        return CodecId::Raw16;
    if (name == "lossless")
        return CodecId::Lossless;
    if (progressiveVariantOf(name))
        return CodecId::Progressive;
    if (Jpeg2000Variant::fromName(name))
        return CodecId::Jpeg2000;
    return std::nullopt;
}

std::unique_ptr<HeightCodec> makeCodec(const std::string& name, double max_error, int level_count)
{
    if (name == "lossless")
        return std::make_unique<LosslessCodec>();
    if (name == "raw")
        return std::make_unique<Raw16Codec>();
    if (const std::optional<ProgressiveVariant> v = progressiveVariantOf(name))
        return std::make_unique<ProgressiveCodec>(max_error, level_count, *v);
    if (const std::optional<Jpeg2000Variant> v = Jpeg2000Variant::fromName(name))
        return std::make_unique<Jpeg2000Codec>(max_error, level_count, *v);
    throw Error("unknown codec '" + name + "' (available: " + kCodecList +
                "; progressive,nested=K for v2 with K levels at the finest bound; "
                "jpeg2000,encoding=progressive|direct,criterion=max|rms|lossless,"
                "library=openjpeg|htj2k)");
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

// The progressive codec: param[0] = δ_l0 in codes (real), param[1] = variant bits
// (ProgressiveVariant::fromBits: v1 0, 2, 4, 6; v2 8 | those | nested_levels << 4), at most 32
// levels (LevelQuantizer shifts by up to 30).
std::string checkProgressiveParameters(const CodecSettings& s)
{
    constexpr ValueRange kMaxErrorCodes = ValueRange::closed(0, 32767);
    if (!kMaxErrorCodes.contains(s.param[0]))
        return "codec_param[0] is " + formatNumber(s.param[0]) +
               ": the progressive codec's finest-level bound δ_l0 (codes) must be " +
               kMaxErrorCodes.describe();
    const double bits = s.param[1];
    if (!(bits >= 0 && bits < 1024 && bits == std::floor(bits) &&
          ProgressiveVariant::fromBits(static_cast<int>(bits))))
        return "codec_param[1] is " + formatNumber(bits) +
               ": the progressive codec's variant must be 0, 2, 4 or 6 (v1: bit 1 cubic "
               "prediction, bit 2 activity contexts) or v2's 8 + those + 16 × nested levels "
               "(1..32)";
    if (s.level_count < 1 || s.level_count > 32)
        return "level_count is " + std::to_string(s.level_count) +
               ": the progressive codec codes 1 to 32 levels";
    return {};
}

// The jpeg2000 codec: param[0] = the criterion's E in codes, param[1] = variant bits
// (Jpeg2000Variant::fromBits); no codec tables.
std::string checkJpeg2000Parameters(const CodecSettings& s)
{
    const double bits = s.param[1];
    const bool known = bits >= 0 && bits < 16 && bits == std::floor(bits) &&
                       Jpeg2000Variant::fromBits(static_cast<int>(bits));
    if (!known)
        return "codec_param[1] is " + formatNumber(bits) +
               ": the jpeg2000 codec's variant must be an integer 0..15 whose bits 1..2 are not 3 "
               "(bit 0 direct, bits 1..2 criterion max/rms/lossless, bit 3 HTJ2K)";
    const bool lossless = Jpeg2000Variant::fromBits(static_cast<int>(bits))->criterion ==
                          CompressionCriterion::Lossless;
    const ValueRange range =
        lossless ? ValueRange::closed(0, 32767) : ValueRange::openClosed(0, 32767);
    if (!range.contains(s.param[0]))
        return "codec_param[0] is " + formatNumber(s.param[0]) +
               ": the jpeg2000 codec's criterion E (codes) must be " + range.describe();
    if (s.level_count < 1 || s.level_count > 32)
        return "level_count is " + std::to_string(s.level_count) +
               ": the jpeg2000 codec codes 1 to 32 levels";
    if (!s.tables.empty())
        return "codec tables are present: the jpeg2000 codec has none";
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
        auto codec = std::make_unique<ProgressiveCodec>(
            settings.param[0], settings.level_count,
            *ProgressiveVariant::fromBits(static_cast<int>(settings.param[1])));
        if (codec->variant().format == 1) {
            if (!settings.tables.empty())
                return rejected(problem, "codec tables are present: the progressive codec's "
                                         "payload v1 has none");
            return codec;
        }
        std::string table_problem;
        auto tables = ProgressiveTables::parse(settings.tables.data(), settings.tables.size(),
                                               settings.level_count, &table_problem);
        if (!tables)
            return rejected(problem, "codec tables: " + table_problem);
        codec->setTables(std::move(tables)); // an archive's codec: fully trained
        return codec;
    }
    case CodecId::Jpeg2000:
        if (std::string p = checkJpeg2000Parameters(settings); !p.empty())
            return rejected(problem, std::move(p));
        return std::make_unique<Jpeg2000Codec>(
            settings.param[0], settings.level_count,
            *Jpeg2000Variant::fromBits(static_cast<int>(settings.param[1])));
    }
    return rejected(problem,
                    "codec_id is " + std::to_string(static_cast<uint32_t>(id)) +
                        ": must be 0 (raw), 1 (lossless), 2 (progressive) or 3 (jpeg2000)");
}

} // namespace ridge
