// Registration of the lossless and raw codecs (ridge/codec/codec_registry.h).
#include "ridge/codec/codec_registry.h"
#include "ridge/codec/lossless_codec.h"
#include "ridge/core/parameter_check.h"

namespace ridge {

namespace {

std::string noOptions(const char* name, const std::string& spec)
{
    if (spec == name)
        return {};
    return std::string("the ") + name + " codec takes no options";
}

// Neither codec has parameters: both stored values must be exactly 0, so that a future
// parameter of theirs cannot be silently ignored by this reader; nor tables.
std::string storedProblem(const char* name, const CodecSettings& s)
{
    for (int k = 0; k < 2; ++k)
        if (!(s.param[k] == 0))
            return "codec_param[" + std::to_string(k) + "] is " + formatNumber(s.param[k]) +
                   ": the " + name + " codec takes no parameters (must be 0)";
    return {};
}

template <class Codec>
std::unique_ptr<HeightCodec> stored(const char* name, const CodecSettings& s, std::string* problem)
{
    if (std::string p = storedProblem(name, s); !p.empty()) {
        if (problem)
            *problem = std::move(p);
        return nullptr;
    }
    return std::make_unique<Codec>();
}

} // namespace

CodecInfo losslessCodec()
{
    return {
        .name = "lossless",
        .id = kLosslessCodecId,
        .description = "MED prediction and zstd, exact (the default)",
        .spec_problem = [](const std::string& spec) { return noOptions("lossless", spec); },
        .from_spec = [](const std::string&, double, int) -> std::unique_ptr<HeightCodec> {
            return std::make_unique<LosslessCodec>();
        },
        .from_settings =
            [](const CodecSettings& s, std::string* problem) {
                return stored<LosslessCodec>("lossless", s, problem);
            },
    };
}

CodecInfo rawCodec()
{
    return {
        .name = "raw",
        .id = kRaw16CodecId,
        .description = "the codes uncompressed (debugging, a speed baseline)",
        .spec_problem = [](const std::string& spec) { return noOptions("raw", spec); },
        .from_spec = [](const std::string&, double, int) -> std::unique_ptr<HeightCodec> {
            return std::make_unique<Raw16Codec>();
        },
        .from_settings = [](const CodecSettings& s,
                            std::string* problem) { return stored<Raw16Codec>("raw", s, problem); },
    };
}

} // namespace ridge
