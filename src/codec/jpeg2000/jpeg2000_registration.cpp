// Registration of the jpeg2000 codec (ridge/codec/codec_registry.h): its options and the
// validation of what an archive stores for it.
#include "ridge/codec/codec_registry.h"
#include "ridge/codec/jpeg2000_codec.h"
#include "ridge/core/parameter_check.h"

#include <cmath>
#include <cstdlib>

namespace ridge {

namespace {

constexpr const char* kOptionForms = "encoding=progressive|direct, criterion=max|rms|lossless, "
                                     "library=openjpeg|htj2k";

// param[0] = the criterion's E in codes, param[1] = variant bits (Jpeg2000Variant::fromBits);
// no codec tables.
std::string parameterProblem(const CodecSettings& s)
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

CodecInfo jpeg2000Codec()
{
    return {
        .name = "jpeg2000",
        .id = kJpeg2000CodecId,
        .description = "the JPEG2000 paper's model: each patch's difference from its parent's "
                       "prediction, JPEG 2000 coded at the rate its criterion needs",
        .lossy = true,
        .option_forms = kOptionForms,
        .spec_problem =
            [](const std::string& spec) {
                return Jpeg2000Variant::fromName(spec)
                           ? std::string()
                           : std::string("the jpeg2000 codec's options are ") + kOptionForms;
            },
        .from_spec = [](const std::string& spec, double max_error,
                        int level_count) -> std::unique_ptr<HeightCodec> {
            return std::make_unique<Jpeg2000Codec>(max_error, level_count,
                                                   *Jpeg2000Variant::fromName(spec));
        },
        .from_settings = [](const CodecSettings& settings,
                            std::string* problem) -> std::unique_ptr<HeightCodec> {
            if (std::string p = parameterProblem(settings); !p.empty()) {
                if (problem)
                    *problem = std::move(p);
                return nullptr;
            }
            return std::make_unique<Jpeg2000Codec>(
                settings.param[0], settings.level_count,
                *Jpeg2000Variant::fromBits(static_cast<int>(settings.param[1])));
        },
        // A build decodes every patch it codes, and OpenJPH 0.9 aborts the process on some
        // malformed codestreams, so HTJ2K is off unless asked for.
        .unavailable = [](const std::string& spec) -> std::string {
            const char* allow = std::getenv("RIDGE_ALLOW_HTJ2K");
            if (Jpeg2000Variant::fromName(spec)->library == Jpeg2000Library::Htj2k &&
                !(allow && std::string(allow) == "1"))
                return "needs RIDGE_ALLOW_HTJ2K=1 in the environment: the build decodes every "
                       "patch it codes, and OpenJPH 0.9 aborts on some malformed codestreams, "
                       "so HTJ2K is off unless asked for";
            return {};
        },
    };
}

} // namespace ridge
