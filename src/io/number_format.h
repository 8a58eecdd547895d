#pragma once
// Numbers in error messages: short, round-trippable enough for a human ("0.05", "nan").
#include <cstdio>
#include <string>

namespace ridge::io::detail {

inline std::string formatNumber(double value, int significant_digits = 10)
{
    char text[64];
    std::snprintf(text, sizeof(text), "%.*g", significant_digits, value);
    return text;
}

} // namespace ridge::io::detail
