#pragma once
// CLI11 validators built from the library's ValueRanges, so that a flag accepts exactly what
// the parameter it sets accepts, and says so readably:
//   ridge: error: --vram 0: must be a number in (0, 1e+06]
// (CLI::PositiveNumber and CLI::Range print their bounds with up to 309 digits, and CLI11
// parses "nan" and "inf" as numbers, which they let through.)
//
// A rejected value throws UsageError rather than returning CLI11's message, so that the
// message is ours (CLI11 would append its own wording) and main exits with the usage status 2
// like every other malformed command line.
#include "usage_error.h"

#include "ridge/core/error.h"
#include "ridge/core/parameter_check.h"

#include <CLI/CLI.hpp>

#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <optional>
#include <string>

namespace ridge::cli {

namespace detail {

// The whole of `text` as a number the way CLI11 reads it (strtod: "nan", "inf" and "1e999",
// which overflows to inf, all parse; the range then rejects them); nullopt for anything else.
inline std::optional<double> parseNumber(const std::string& text)
{
    if (text.empty())
        return std::nullopt;
    char* end = nullptr;
    errno = 0;
    const double value = std::strtod(text.c_str(), &end);
    if (end != text.c_str() + text.size())
        return std::nullopt;
    return value;
}

// `text` as a base-10 integer; nullopt for anything else (including out of int64 range).
inline std::optional<int64_t> parseInteger(const std::string& text)
{
    if (text.empty())
        return std::nullopt;
    char* end = nullptr;
    errno = 0;
    const long long value = std::strtoll(text.c_str(), &end, 10);
    if (end != text.c_str() + text.size() || errno == ERANGE)
        return std::nullopt;
    return int64_t{value};
}

// "--sun 500: the altitude must be a number in (0, 90]".
[[noreturn]] inline void reject(const std::string& flag, const std::string& text,
                                const std::string& what, const std::string& range)
{
    throw UsageError(flag + " " + text + ": " + (what.empty() ? "" : what + " ") + "must be " + range);
}

} // namespace detail

// A number within `range`. `what` names the component for flags of several numbers
// ("each coordinate", "the altitude"); use Validator::application_index for one of them.
inline CLI::Validator inRange(const std::string& flag, ValueRange range, std::string what = "")
{
    return CLI::Validator(
        [flag, range, what](std::string& text) -> std::string {
            const std::optional<double> value = detail::parseNumber(text);
            if (!value || !range.contains(*value))
                detail::reject(flag, text, what, range.describe());
            return {};
        },
        range.describe());
}

// A number whose magnitude lies within `range` (either sign): --z-scale.
inline CLI::Validator magnitudeInRange(const std::string& flag, ValueRange range)
{
    return CLI::Validator(
        [flag, range](std::string& text) -> std::string {
            const std::optional<double> value = detail::parseNumber(text);
            if (!value || !range.contains(std::abs(*value)))
                detail::reject(flag, text, "its magnitude", range.describe());
            return {};
        },
        "magnitude: " + range.describe());
}

// An integer in [lo, hi].
inline CLI::Validator inIntegerRange(const std::string& flag, int64_t lo, int64_t hi,
                                     std::string what = "")
{
    const std::string range =
        "an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
    return CLI::Validator(
        [flag, lo, hi, what, range](std::string& text) -> std::string {
            const std::optional<int64_t> value = detail::parseInteger(text);
            if (!value || *value < lo || *value > hi)
                detail::reject(flag, text, what, range);
            return {};
        },
        range);
}

} // namespace ridge::cli
