#include "ridge/core/parameter_check.h"

#include "ridge/core/error.h"

#include <charconv>
#include <cmath>

namespace ridge {

bool ValueRange::contains(double value) const
{
    if (!std::isfinite(value))
        return false;
    const bool above_lo = lo_open ? value > lo : value >= lo;
    const bool below_hi = hi_open ? value < hi : value <= hi;
    return above_lo && below_hi;
}

std::string ValueRange::describe() const
{
    const bool has_lo = std::isfinite(lo), has_hi = std::isfinite(hi);
    if (!has_lo && !has_hi)
        return "a finite number";
    if (!has_hi)
        return std::string("a finite number ") + (lo_open ? "> " : ">= ") + formatNumber(lo);
    if (!has_lo)
        return std::string("a finite number ") + (hi_open ? "< " : "<= ") + formatNumber(hi);
    return std::string("a number in ") + (lo_open ? "(" : "[") + formatNumber(lo) + ", " +
           formatNumber(hi) + (hi_open ? ")" : "]");
}

std::string formatNumber(double value)
{
    if (std::isnan(value))
        return "nan";
    if (std::isinf(value))
        return value > 0 ? "inf" : "-inf";
    char buf[32];
    const auto result = std::to_chars(buf, buf + sizeof buf, value);
    return std::string(buf, result.ptr);
}

void checkParameter(std::string_view name, double value, ValueRange range)
{
    if (!range.contains(value))
        throw Error(std::string(name) + " is " + formatNumber(value) + ": must be " +
                    range.describe());
}

void checkParameter(std::string_view name, int64_t value, int64_t lo, int64_t hi)
{
    if (value < lo || value > hi)
        throw Error(std::string(name) + " is " + std::to_string(value) +
                    ": must be an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) +
                    "]");
}

void checkParameters(std::string_view name, const double* values, int count, ValueRange range)
{
    bool ok = true;
    for (int k = 0; k < count; ++k)
        ok = ok && range.contains(values[k]);
    if (ok)
        return;
    std::string text = "(";
    for (int k = 0; k < count; ++k)
        text += (k ? ", " : "") + formatNumber(values[k]);
    throw Error(std::string(name) + " is " + text + "): every component must be " +
                range.describe());
}

} // namespace ridge
