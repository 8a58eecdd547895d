// LOD schemes' own options: descriptors, the KEY=VALUE parser and the values modules read
// (ridge/render/scheme_options.h). GL-free; the registry's side is in scheme_registry.cpp.
#include "ridge/render/scheme_options.h"

#include "ridge/core/error.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <optional>
#include <system_error>

namespace ridge::render {
namespace {

using Kind = SchemeOption::Kind;

const char* kindName(Kind kind)
{
    switch (kind) {
    case Kind::Number:
        return "number";
    case Kind::Integer:
        return "integer";
    case Kind::Choice:
        return "choice";
    case Kind::Flag:
        return "on/off";
    }
    return "?";
}

// Decimal digits with an optional sign, point and exponent, or inf, infinity and nan in any
// case (which the range then refuses by name), the whole of `text`; nothing else (no
// hexadecimal, no blanks). A magnitude beyond double's overflows to ±inf.
std::optional<double> parseNumber(std::string_view text)
{
    std::string_view body = text;
    bool negative = false;
    if (!body.empty() && (body[0] == '+' || body[0] == '-')) {
        negative = body[0] == '-';
        body.remove_prefix(1);
    }
    if (body.empty() || body[0] == '+' || body[0] == '-')
        return std::nullopt;
    // from_chars takes hexadecimal floats only with chars_format::hex: general is decimal.
    double value = 0.0;
    const auto [end, error] =
        std::from_chars(body.data(), body.data() + body.size(), value, std::chars_format::general);
    if (end != body.data() + body.size())
        return std::nullopt;
    if (error == std::errc::result_out_of_range) {
        // Overflow (1e999) or underflow (1e-999): which one, from the exponent's sign.
        const size_t e = body.find_first_of("eE");
        const bool tiny = e != std::string_view::npos && e + 1 < body.size() && body[e + 1] == '-';
        value = tiny ? 0.0 : std::numeric_limits<double>::infinity();
    } else if (error != std::errc()) {
        return std::nullopt;
    }
    return negative ? -value : value;
}

std::optional<int64_t> parseInteger(std::string_view text)
{
    std::string_view body = text;
    if (!body.empty() && body[0] == '+')
        body.remove_prefix(1);
    if (body.empty() || body[0] == '+')
        return std::nullopt;
    int64_t value = 0;
    const auto [end, error] = std::from_chars(body.data(), body.data() + body.size(), value);
    if (error != std::errc() || end != body.data() + body.size())
        return std::nullopt;
    return value;
}

[[noreturn]] void fail(const std::string& prefix, const std::string& message)
{
    throw Error(prefix + message);
}

std::string joined(const std::vector<std::string>& names)
{
    std::string out;
    for (const std::string& n : names)
        out += (out.empty() ? "" : ", ") + n;
    return out;
}

} // namespace

SchemeOption SchemeOption::number(std::string key, std::string help, ValueRange range,
                                  double default_value)
{
    SchemeOption o;
    o.key = std::move(key);
    o.help = std::move(help);
    o.kind = Kind::Number;
    o.range = range;
    o.default_value = formatNumber(default_value);
    return o;
}

SchemeOption SchemeOption::integer(std::string key, std::string help, int64_t min, int64_t max,
                                   int64_t default_value)
{
    SchemeOption o;
    o.key = std::move(key);
    o.help = std::move(help);
    o.kind = Kind::Integer;
    o.min = min;
    o.max = max;
    o.default_value = std::to_string(default_value);
    return o;
}

SchemeOption SchemeOption::choice(std::string key, std::string help,
                                  std::vector<std::string> choices, std::string default_value)
{
    SchemeOption o;
    o.key = std::move(key);
    o.help = std::move(help);
    o.kind = Kind::Choice;
    o.choices = std::move(choices);
    o.default_value = std::move(default_value);
    return o;
}

SchemeOption SchemeOption::flag(std::string key, std::string help, bool default_value)
{
    SchemeOption o;
    o.key = std::move(key);
    o.help = std::move(help);
    o.kind = Kind::Flag;
    o.default_value = default_value ? "on" : "off";
    return o;
}

std::string SchemeOption::describe() const
{
    switch (kind) {
    case Kind::Number:
        return range.describe();
    case Kind::Integer:
        return "an integer in [" + std::to_string(min) + ", " + std::to_string(max) + "]";
    case Kind::Choice:
        return "one of " + joined(choices);
    case Kind::Flag:
        return "on or off";
    }
    return {};
}

std::string SchemeOption::placeholder() const
{
    switch (kind) {
    case Kind::Number:
        return "X";
    case Kind::Integer:
        return "N";
    case Kind::Choice: {
        std::string out;
        for (const std::string& c : choices)
            out += (out.empty() ? "" : "|") + c;
        return out;
    }
    case Kind::Flag:
        return "on|off";
    }
    return {};
}

const SchemeOptions::Value& SchemeOptions::at(std::string_view key, Kind kind) const
{
    for (const Value& v : values_)
        if (v.key == key && v.kind == kind)
            return v;
    throw Error("LOD scheme " + (scheme_.empty() ? std::string("(none)") : scheme_) +
                " declares no " + kindName(kind) + " option '" + std::string(key) + "'");
}

double SchemeOptions::number(std::string_view key) const
{
    return at(key, Kind::Number).number;
}

int64_t SchemeOptions::integer(std::string_view key) const
{
    return at(key, Kind::Integer).integer;
}

const std::string& SchemeOptions::choice(std::string_view key) const
{
    return at(key, Kind::Choice).text;
}

bool SchemeOptions::flag(std::string_view key) const
{
    return at(key, Kind::Flag).flag;
}

std::string SchemeOptions::spec() const
{
    std::string out = scheme_;
    for (const Value& v : values_)
        out += "," + v.key + "=" + v.text;
    return out;
}

SchemeOptions parseSchemeOptions(const std::string& scheme,
                                 const std::vector<SchemeOption>& declared, std::string_view pairs,
                                 std::string_view what)
{
    const std::string prefix = std::string(what) + " " + scheme + ": ";

    // The value of `option` spelt `text`, or an error naming both.
    auto valueOf = [&](const SchemeOption& option, std::string_view text) {
        SchemeOptions::Value v{option.key, option.kind, std::string(text)};
        bool ok = false;
        switch (option.kind) {
        case Kind::Number:
            if (const std::optional<double> x = parseNumber(text)) {
                v.number = *x;
                v.text = formatNumber(*x);
                ok = option.range.contains(*x);
            }
            break;
        case Kind::Integer:
            if (const std::optional<int64_t> n = parseInteger(text)) {
                v.integer = *n;
                v.text = std::to_string(*n);
                ok = *n >= option.min && *n <= option.max;
            }
            break;
        case Kind::Choice:
            ok = std::find(option.choices.begin(), option.choices.end(), text) !=
                 option.choices.end();
            break;
        case Kind::Flag:
            ok = text == "on" || text == "off";
            v.flag = text == "on";
            break;
        }
        if (!ok)
            fail(prefix, option.key + "=" + std::string(text) + ": must be " + option.describe());
        return v;
    };

    std::vector<std::optional<SchemeOptions::Value>> given(declared.size());
    if (!pairs.empty()) {
        size_t start = 0;
        while (true) {
            const size_t comma = pairs.find(',', start);
            const std::string_view pair = pairs.substr(
                start, comma == std::string_view::npos ? std::string_view::npos : comma - start);
            if (pair.empty())
                fail(prefix, "an empty option (expected " + scheme + ",KEY=VALUE,...)");
            const size_t eq = pair.find('=');
            if (eq == std::string_view::npos || eq == 0 || eq + 1 == pair.size())
                fail(prefix, "'" + std::string(pair) + "' is not KEY=VALUE");
            const std::string_view key = pair.substr(0, eq);
            const auto it = std::find_if(declared.begin(), declared.end(),
                                         [&](const SchemeOption& o) { return o.key == key; });
            if (it == declared.end()) {
                std::vector<std::string> keys;
                for (const SchemeOption& o : declared)
                    keys.push_back(o.key);
                fail(prefix,
                     "no option '" + std::string(key) + "' (" + scheme +
                         (keys.empty() ? " takes no options)" : " takes " + joined(keys) + ")"));
            }
            std::optional<SchemeOptions::Value>& slot = given[size_t(it - declared.begin())];
            if (slot)
                fail(prefix, std::string(key) + " given twice");
            slot = valueOf(*it, pair.substr(eq + 1));
            if (comma == std::string_view::npos)
                break;
            start = comma + 1;
        }
    }

    SchemeOptions out;
    out.scheme_ = scheme;
    for (size_t k = 0; k < declared.size(); ++k)
        out.values_.push_back(given[k] ? *given[k]
                                       : valueOf(declared[k], declared[k].default_value));
    return out;
}

} // namespace ridge::render
