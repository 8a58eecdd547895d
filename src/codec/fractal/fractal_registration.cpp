// Registration of the fractal codec (ridge/codec/codec_registry.h): its options and the
// validation of what an archive stores for it.
#include "ridge/codec/codec_registry.h"
#include "ridge/codec/fractal_codec.h"
#include "ridge/core/parameter_check.h"

#include <cmath>
#include <optional>

namespace ridge {

namespace {

constexpr const char* kOptionForms =
    "iterations=N (1..32 applications of T when decoding, default 8), search=R (0..1024 "
    "domain positions around each range block, 0 = the whole patch; default 8)";

// "fractal[,iterations=N][,search=R]"; nullopt for anything else.
std::optional<FractalVariant> variantOf(const std::string& spec)
{
    const std::string base = "fractal";
    if (spec.rfind(base, 0) != 0)
        return std::nullopt;
    FractalVariant v;
    if (spec.size() == base.size())
        return v;
    if (spec[base.size()] != ',')
        return std::nullopt;
    size_t at = base.size() + 1;
    while (at <= spec.size()) {
        const size_t comma = std::min(spec.find(',', at), spec.size());
        const std::string option = spec.substr(at, comma - at);
        const size_t eq = option.find('=');
        if (eq == std::string::npos)
            return std::nullopt;
        const std::string key = option.substr(0, eq), value = option.substr(eq + 1);
        if (value.empty() || value.size() > 4 ||
            value.find_first_not_of("0123456789") != std::string::npos)
            return std::nullopt;
        const int number = std::stoi(value);
        if (key == "iterations" && number >= 1 && number <= FractalVariant::kMaxIterations)
            v.iterations = number;
        else if (key == "search" && number <= FractalVariant::kMaxSearch)
            v.search = number;
        else
            return std::nullopt;
        at = comma + 1;
    }
    return v;
}

// param[0] = the bound E in whole codes, param[1] = iterations; no codec tables.
std::string parameterProblem(const CodecSettings& s)
{
    if (!(s.param[0] >= 0 && s.param[0] <= 32767 && s.param[0] == std::floor(s.param[0])))
        return "codec_param[0] is " + formatNumber(s.param[0]) +
               ": the fractal codec's bound E must be a whole number of codes in [0, 32767]";
    if (!(s.param[1] >= 1 && s.param[1] <= FractalVariant::kMaxIterations &&
          s.param[1] == std::floor(s.param[1])))
        return "codec_param[1] is " + formatNumber(s.param[1]) +
               ": the fractal codec's iterations must be a whole number in [1, 32]";
    if (s.level_count < 1 || s.level_count > 32)
        return "level_count is " + std::to_string(s.level_count) +
               ": the fractal codec codes 1 to 32 levels";
    if (!s.tables.empty())
        return "codec tables are present: the fractal codec has none";
    return {};
}

} // namespace

CodecInfo fractalCodec()
{
    return {
        .name = "fractal",
        .id = kFractalCodecId,
        .description = "the fractal-rings paper's PIFS (4×4 range blocks, 8×8 domain blocks, "
                       "least-squares s and o), decoded by iteration, with shared edges and "
                       "corrections that keep every sample within its bound",
        .lossy = true,
        .option_forms = kOptionForms,
        .spec_problem =
            [](const std::string& spec) {
                return variantOf(spec)
                           ? std::string()
                           : std::string("the fractal codec's options are ") + kOptionForms;
            },
        .from_spec = [](const std::string& spec, double max_error,
                        int level_count) -> std::unique_ptr<HeightCodec> {
            return std::make_unique<FractalCodec>(max_error, level_count, *variantOf(spec));
        },
        .from_settings = [](const CodecSettings& settings,
                            std::string* problem) -> std::unique_ptr<HeightCodec> {
            if (std::string p = parameterProblem(settings); !p.empty()) {
                if (problem)
                    *problem = std::move(p);
                return nullptr;
            }
            FractalVariant v;
            v.iterations = int(settings.param[1]);
            return std::make_unique<FractalCodec>(settings.param[0], settings.level_count, v);
        },
    };
}

} // namespace ridge
