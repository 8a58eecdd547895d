// Registration of the progressive codec (ridge/codec/codec_registry.h): its named variants,
// its options and the validation of what an archive stores for it.
#include "ridge/codec/codec_registry.h"
#include "ridge/codec/progressive_codec.h"
#include "ridge/codec/progressive_tables.h"
#include "ridge/core/parameter_check.h"

#include <cmath>
#include <optional>

namespace ridge {

namespace {

// A variant by spec: "progressive" (payload v4), "progressive-v3", "progressive-v2",
// "progressive-v1", "progressive-paper", and v4 with options for measurement,
// "progressive,nested=K,corrections=0|1,payload=2|3|4". Null for anything else.
std::optional<ProgressiveVariant> variantOf(const std::string& spec)
{
    if (spec == "progressive")
        return ProgressiveVariant{};
    if (spec == "progressive-v1")
        return ProgressiveVariant::v1();
    if (spec == "progressive-v3")
        return ProgressiveVariant::v3();
    if (spec == "progressive-v2")
        return ProgressiveVariant::v2();
    if (spec == "progressive-paper")
        return ProgressiveVariant::paper();
    if (spec.rfind("progressive,", 0) != 0)
        return std::nullopt;
    ProgressiveVariant v;
    const bool valid =
        forEachSpecOption(spec, "progressive", [&](const auto& key, const auto& value) {
            if (key == "nested") {
                const auto k = specNumber(value, 1, 32);
                v.nested_levels = k.value_or(0);
                return k.has_value();
            }
            if (key == "payload") {
                const auto f = specNumber(value, 2, 4);
                v.format = f.value_or(0);
                return f.has_value();
            }
            if (key == "corrections") {
                const auto c = specNumber(value, 0, 1);
                v.corrections = c == 1;
                return c.has_value();
            }
            return false;
        });
    return valid ? std::optional(v) : std::nullopt;
}

constexpr const char* kOptionForms = "nested=K (1..32 finest levels at the finest bound), "
                                     "corrections=0|1 (least-squares prediction corrections), "
                                     "payload=2|3|4 (payload version)";

std::unique_ptr<HeightCodec> rejected(std::string* problem, std::string text)
{
    if (problem)
        *problem = std::move(text);
    return nullptr;
}

// param[0] = δ_l0 in codes (real), param[1] = variant bits (ProgressiveVariant::fromBits: v1
// 0, 2, 4, 6; v2 8 | those | nested_levels << 4; v3 1024 | v2's; v4 2048 | v2's), at most 32
// levels (LevelQuantizer
// shifts by up to 30).
std::string parameterProblem(const CodecSettings& s)
{
    constexpr ValueRange kMaxErrorCodes = ValueRange::closed(0, 32767);
    if (!kMaxErrorCodes.contains(s.param[0]))
        return "codec_param[0] is " + formatNumber(s.param[0]) +
               ": the progressive codec's finest-level bound δ_l0 (codes) must be " +
               kMaxErrorCodes.describe();
    const double bits = s.param[1];
    if (!(bits >= 0 && bits < 2 * ProgressiveVariant::kPayloadV4Bit && bits == std::floor(bits) &&
          ProgressiveVariant::fromBits(static_cast<int>(bits))))
        return "codec_param[1] is " + formatNumber(bits) +
               ": the progressive codec's variant must be 0, 2, 4 or 6 (v1: bit 1 cubic "
               "prediction, bit 2 activity contexts), v2's 8 + those + 16 × nested levels "
               "(1..32), v3's 1024 + v2's or v4's 2048 + v2's";
    if (s.level_count < 1 || s.level_count > 32)
        return "level_count is " + std::to_string(s.level_count) +
               ": the progressive codec codes 1 to 32 levels";
    return {};
}

std::unique_ptr<HeightCodec> fromSettings(const CodecSettings& settings, std::string* problem)
{
    if (std::string p = parameterProblem(settings); !p.empty())
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
                                           settings.level_count, codec->variant().tableContexts(),
                                           &table_problem);
    if (!tables)
        return rejected(problem, "codec tables: " + table_problem);
    codec->setTables(std::move(tables)); // an archive's codec: fully trained
    return codec;
}

} // namespace

CodecInfo progressiveCodec()
{
    return {
        .name = "progressive",
        .id = kProgressiveCodecId,
        .description = "the hardware-tessellation paper's progressive L∞ codec, v4: every "
                       "sample within its bound, decoded on the GPU",
        .lossy = true,
        .finest_first = true, // reconstruct() is the level's quantizer alone
        .aliases = {"progressive-v3", "progressive-v2", "progressive-v1", "progressive-paper"},
        .option_forms = kOptionForms,
        .spec_problem =
            [](const std::string& spec) {
                return variantOf(spec)
                           ? std::string()
                           : std::string("the progressive codec's options are ") + kOptionForms +
                                 " (progressive-v3, progressive-v2, progressive-v1 and "
                                 "progressive-paper take none)";
            },
        .from_spec = [](const std::string& spec, double max_error,
                        int level_count) -> std::unique_ptr<HeightCodec> {
            return std::make_unique<ProgressiveCodec>(max_error, level_count, *variantOf(spec));
        },
        .from_settings = fromSettings,
    };
}

} // namespace ridge
