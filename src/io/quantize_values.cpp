// Bands that are not 8/16-bit integers: a strip-wise pre-pass finds the valid range and
// whether every value is an integer, which settles the code -> metre mapping; reading then
// converts each strip of values to codes.
#include "code_source.h"

#include "number_format.h"

#include <algorithm>
#include <cfloat>
#include <cmath>

namespace ridge::io::detail {

namespace {

constexpr int64_t kCodeCount = int64_t{UINT16_MAX} + 1;
// Integers beyond this are not all representable as doubles.
constexpr double kLargestExactInteger = 9007199254740992.0; // 2^53

struct ValueSurvey {
    double min_value = INFINITY;
    double max_value = -INFINITY;
    bool integral = true;
    int64_t valid = 0;
    int64_t voids = 0;
};

ValueSurvey survey(const SourceBand& band, const Progress& progress)
{
    ValueSurvey s;
    const int width = band.width();
    const int height = band.height();
    const int strip_rows = band.stripRows(kStripBytes, sizeof(double));
    std::vector<double> strip(static_cast<size_t>(strip_rows) * width);
    std::vector<uint8_t> mask_scratch;
    std::vector<double> undulations;
    // A geoid shift adds N in metres; in stored units that is N / z_scale (never 0).
    const double per_metre = 1.0 / band.z().scale;
    s.integral = band.geoidShift() == nullptr;
    for (int y0 = 0; y0 < height; y0 += strip_rows) {
        const int rows = std::min(strip_rows, height - y0);
        band.readValues(y0, rows, strip.data(), mask_scratch);
        band.readUndulations(y0, rows, undulations);
        for (size_t i = 0; i < static_cast<size_t>(rows) * width; ++i) {
            double v = strip[i];
            if (std::isnan(v)) {
                ++s.voids;
                continue;
            }
            if (!undulations.empty())
                v += undulations[i] * per_metre;
            ++s.valid;
            s.min_value = std::min(s.min_value, v);
            s.max_value = std::max(s.max_value, v);
            s.integral = s.integral && std::floor(v) == v && std::abs(v) <= kLargestExactInteger;
        }
        reportProgress(progress, double(y0 + rows) / height);
    }
    return s;
}

// Rounds `x` up to 3 significant digits, for a suggestion that certainly works.
double roundUpForHumans(double x)
{
    const double magnitude = std::pow(10.0, std::floor(std::log10(x)) - 2);
    return std::ceil(x / magnitude) * magnitude;
}

// Step in metres such that every valid value is within max_error of its code's height.
double stepFor(const SourceBand& band, double range, double magnitude, int64_t max_code,
               const std::optional<double>& max_error)
{
    if (!max_error)
        return range > 0 ? range / double(max_code) : 1.0;
    // Rounding to the nearest step errs by at most step / 2; the margin absorbs the double
    // rounding of (m - offset) / step and offset + step * code at this magnitude.
    const double margin = 16 * DBL_EPSILON * std::max(magnitude, *max_error);
    const double step = 2 * (*max_error - margin);
    if (step > 0 && range <= step * double(max_code))
        return step;
    const double needed = roundUpForHumans((range / double(max_code) / 2 + margin) * (1 + 1e-9));
    const double codes_needed = std::ceil(range / (2 * *max_error)) + 1;
    band.fail("height range " + formatNumber(range, 6) + " m needs " +
              formatNumber(codes_needed, 6) + " codes at max_error " + formatNumber(*max_error, 6) +
              " but 16 bits hold " + std::to_string(max_code + 1) + "; max_error " +
              formatNumber(needed, 3) + " or larger would work");
}

class QuantizedCodes final : public CodeSource {
  public:
    QuantizedCodes(const SourceBand& band, const CodeMapping& planned) : band_(band)
    {
        exact_ = planned.exact;
        integer_origin_ = planned.integer_origin;
        max_code_ = planned.max_code;
        quantization_.scale = planned.quantization.scale;
        quantization_.offset = planned.quantization.offset;
        planned_max_error_ = planned.quantization.max_error;
    }

    QuantizedCodes(const SourceBand& band, const std::optional<double>& max_error,
                   const Progress& survey_progress)
        : band_(band)
    {
        const ValueSurvey s = survey(band, survey_progress);
        if (s.valid == 0)
            band.fail("all samples are nodata");
        band.checkHeightRange(s.min_value, s.max_value, "its values");
        const ZTransform& z = band.z();
        const double min_metres = std::min(z.toMetres(s.min_value), z.toMetres(s.max_value));
        const double max_metres = std::max(z.toMetres(s.min_value), z.toMetres(s.max_value));
        exact_ = s.integral && s.max_value - s.min_value < double(kCodeCount);
        if (exact_) {
            // Integers: code = value - min, exactly as for Int16; from the maximum down when
            // z_scale < 0 so that the code -> metre scale stays positive.
            const bool mirrored = z.scale < 0;
            integer_origin_ = mirrored ? s.max_value : s.min_value;
            quantization_.scale = std::abs(z.scale);
            quantization_.offset = z.toMetres(integer_origin_);
            max_code_ = static_cast<int64_t>(s.max_value - s.min_value);
        } else {
            // With voids the top code stays free so that void filling can spot unfilled voids.
            max_code_ = s.voids > 0 ? kCodeCount - 2 : kCodeCount - 1;
            const double range = max_metres - min_metres;
            const double magnitude = std::max(std::abs(min_metres), std::abs(max_metres));
            quantization_.scale = stepFor(band, range, magnitude, max_code_, max_error);
            quantization_.offset = min_metres;
        }
    }

    int stripSampleBytes() const override { return sizeof(double); }

    std::optional<CodeMapping> mapping() const override
    {
        return CodeMapping{
            exact_, integer_origin_, max_code_, {quantization_.scale, quantization_.offset, 0.0}};
    }

    void readRows(int y0, int rows, uint16_t* out, std::vector<int64_t>& voids, CodeStats& stats,
                  uint8_t* water) override
    {
        const size_t count = static_cast<size_t>(rows) * band_.width();
        values_.resize(count);
        band_.readValues(y0, rows, values_.data(), mask_scratch_);
        band_.readUndulations(y0, rows, undulations_);
        const ZTransform& z = band_.z();
        const HeightQuantization& q = quantization_;
        uint16_t lo = UINT16_MAX;
        uint16_t hi = 0;
        for (size_t i = 0; i < count; ++i) {
            const double v = values_[i];
            if (std::isnan(v)) {
                voids.push_back(static_cast<int64_t>(i));
                if (water)
                    water[i] = 0;
                continue;
            }
            const double source_metres = z.toMetres(v);
            // The source's value, not its code: a 0 m sea quantized to +1 mm is sea; and
            // before a geoid shift, since sea level is the geoid's business.
            if (water)
                water[i] = sea_level_ && source_metres <= *sea_level_;
            const double m = undulations_.empty() ? source_metres : source_metres + undulations_[i];
            uint16_t code;
            if (exact_) {
                const double d = std::abs(v - integer_origin_);
                if (planned_max_error_ && !(d <= double(max_code_) && std::floor(v) == v))
                    outsidePlan(y0, i, v);
                code = static_cast<uint16_t>(d);
            } else {
                code = static_cast<uint16_t>(
                    std::clamp<long long>(std::llround((m - q.offset) / q.scale), 0, max_code_));
                const double error = std::abs(q.toMetres(code) - m);
                if (planned_max_error_ && !(error <= *planned_max_error_))
                    outsidePlan(y0, i, v);
                stats.max_error = std::max(stats.max_error, error);
            }
            out[i] = code;
            lo = std::min(lo, code);
            hi = std::max(hi, code);
            stats.min_metres = std::min(stats.min_metres, m);
            stats.max_metres = std::max(stats.max_metres, m);
            ++stats.valid;
        }
        if (lo <= hi)
            stats.addCodes(lo, hi);
    }

  private:
    [[noreturn]] void outsidePlan(int y0, size_t i, double v) const
    {
        band_.fail("value " + formatNumber(v, 9) + " at row " +
                   std::to_string(y0 + int64_t(i) / band_.width()) +
                   " is not one the planned code mapping holds: the raster changed since it "
                   "was planned");
    }

    const SourceBand& band_;
    std::optional<double> planned_max_error_; // a planned mapping's bound, checked per value
    double integer_origin_ = 0.0;
    int64_t max_code_ = kCodeCount - 1;
    std::vector<double> values_;
    std::vector<double> undulations_;
    std::vector<uint8_t> mask_scratch_;
};

} // namespace

std::unique_ptr<CodeSource> makeQuantizedCodes(const SourceBand& band,
                                               const std::optional<double>& max_error,
                                               const Progress& survey_progress,
                                               const CodeMapping* planned)
{
    if (planned)
        return std::make_unique<QuantizedCodes>(band, *planned);
    return std::make_unique<QuantizedCodes>(band, max_error, survey_progress);
}

} // namespace ridge::io::detail
