#pragma once
// CLI11 validators built from the library's ValueRanges, so that a flag accepts exactly what
// the parameter it sets accepts, and says so readably:
//   ridge: error: --vram 0: must be a number in (0, 1e+06]
// (CLI::PositiveNumber and CLI::Range print their bounds with up to 309 digits, and CLI11
// parses "nan" and "inf" as numbers, which they let through.) Every number is spelt by one
// rule (detail::isDecimalNumber), which main() also applies to the numeric options that have
// no range of their own.
//
// A rejected value throws UsageError rather than returning CLI11's message, so that the
// message is ours (CLI11 would append its own wording) and main exits with the usage status 2
// like every other malformed command line.
#include "usage_error.h"

#include "ridge/core/error.h"
#include "ridge/core/parameter_check.h"

#include <CLI/CLI.hpp>

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <optional>
#include <string>
#include <string_view>

namespace ridge::cli {

namespace detail {

// One spelling rule for every number on the command line, in every flag, positional and
// stdin line alike: decimal digits with an optional sign, decimal point and exponent ("12",
// "-0.5", ".5", "1e-3"), or inf, infinity and nan in any case (which every range then refuses
// by name, rather than calling them malformed). No hexadecimal ("0x10" read as 16 where
// another flag refused it), no blanks around, nothing after.
inline bool isDecimalNumber(std::string_view text)
{
    size_t at = 0;
    if (at < text.size() && (text[at] == '+' || text[at] == '-'))
        ++at;
    std::string word(text.substr(at));
    for (char& c : word)
        c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (word == "inf" || word == "infinity" || word == "nan")
        return true;
    auto digits = [&] {
        const size_t start = at;
        while (at < text.size() && text[at] >= '0' && text[at] <= '9')
            ++at;
        return at - start;
    };
    size_t mantissa = digits();
    if (at < text.size() && text[at] == '.') {
        ++at;
        mantissa += digits();
    }
    if (mantissa == 0)
        return false;
    if (at < text.size() && (text[at] == 'e' || text[at] == 'E')) {
        ++at;
        if (at < text.size() && (text[at] == '+' || text[at] == '-'))
            ++at;
        if (digits() == 0)
            return false;
    }
    return at == text.size();
}

// An integer under the same rule: decimal digits with an optional sign.
inline bool isDecimalInteger(std::string_view text)
{
    size_t at = text.size() > 0 && (text[0] == '+' || text[0] == '-') ? 1 : 0;
    return at < text.size() && text.find_first_not_of("0123456789", at) == std::string_view::npos;
}

// The whole of `text` as a number (isDecimalNumber; "1e999" overflows to inf, which the
// ranges then refuse); nullopt for anything else.
inline std::optional<double> parseNumber(const std::string& text)
{
    if (!isDecimalNumber(text))
        return std::nullopt;
    return std::strtod(text.c_str(), nullptr);
}

// `text` as a base-10 integer; nullopt for anything else (including out of int64 range).
inline std::optional<int64_t> parseInteger(const std::string& text)
{
    if (!isDecimalInteger(text))
        return std::nullopt;
    errno = 0;
    const long long value = std::strtoll(text.c_str(), nullptr, 10);
    if (errno == ERANGE)
        return std::nullopt;
    return int64_t{value};
}

// "--sun 500: the altitude must be a number in (0, 90]".
[[noreturn]] inline void reject(const std::string& flag, const std::string& text,
                                const std::string& what, const std::string& range)
{
    throw UsageError(flag + " " + text + ": " + (what.empty() ? "" : what + " ") + "must be " +
                     range);
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
