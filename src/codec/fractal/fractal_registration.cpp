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
    "domain positions around each range block, 0 = the whole patch; default 8), "
    "mode=bounded|paper (paper: the transforms alone, no bound — codec-bench only)";

// "fractal[,iterations=N][,search=R][,mode=bounded|paper]"; nullopt for anything else.
std::optional<FractalVariant> variantOf(const std::string& spec)
{
    FractalVariant v;
    const bool valid = forEachSpecOption(spec, "fractal", [&](const auto& key, const auto& value) {
        if (key == "mode" && (value == "paper" || value == "bounded")) {
            v.paper = value == "paper";
            return true;
        }
        if (key == "iterations") {
            const auto n = specNumber(value, 1, FractalVariant::kMaxIterations);
            v.iterations = n.value_or(0);
            return n.has_value();
        }
        if (key == "search") {
            const auto r = specNumber(value, 0, FractalVariant::kMaxSearch);
            v.search = r.value_or(0);
            return r.has_value();
        }
        return false;
    });
    return valid ? std::optional(v) : std::nullopt;
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
        .bench_variants = {"fractal,mode=paper"},
    };
}

} // namespace ridge
