#pragma once
// Values a LOD scheme's option must refuse, derived from its descriptor (ridge/render/
// scheme_options.h), so that the tests of the spec parser and of the command line cover every
// option of every registered scheme without naming one.
#include "ridge/core/parameter_check.h"
#include "ridge/render/scheme_options.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <string>
#include <vector>

namespace ridge::test {

// Values `o` refuses, each reported as "KEY=VALUE: must be ...": NaN, infinities, numbers just
// outside its range, malformed numbers, unknown names.
inline std::vector<std::string> refusedValues(const render::SchemeOption& o)
{
    using Kind = render::SchemeOption::Kind;
    std::vector<std::string> out;
    switch (o.kind) {
    case Kind::Number:
        out = {"nan", "inf", "-inf", "1e999", "abc", "0x10", "1e", "1 "};
        if (std::isfinite(o.range.lo))
            out.push_back(formatNumber(
                o.range.lo_open ? o.range.lo : o.range.lo - std::max(1.0, std::abs(o.range.lo))));
        if (std::isfinite(o.range.hi))
            out.push_back(formatNumber(
                o.range.hi_open ? o.range.hi : o.range.hi + std::max(1.0, std::abs(o.range.hi))));
        break;
    case Kind::Integer:
        out = {std::to_string(o.min - 1), std::to_string(o.max + 1), "1.5", "abc", "nan",
               "99999999999999999999"};
        break;
    case Kind::Choice: {
        out = {"no-such-choice"};
        std::string upper = o.choices.front();
        for (char& c : upper)
            c = char(std::toupper(static_cast<unsigned char>(c)));
        if (upper != o.choices.front())
            out.push_back(upper);
        break;
    }
    case Kind::Flag:
        out = {"yes", "ON", "1", "true"};
        break;
    }
    return out;
}

} // namespace ridge::test
