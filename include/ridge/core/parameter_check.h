#pragma once
// Checks of numeric parameters where they enter the library (cameras, ε, budgets, z-scale,
// spacing ...). NaN and infinities slip through ordinary comparisons (`x < 0` is false for
// NaN), so every check here asks "is the value inside the range" and a NaN never is.
//
// Messages name the parameter as the API spells it and state the range readably:
//   "epsilon_px is nan: must be a finite number in [0.05, 1000]"
// Command-line tools map the same ranges to their flags (ValueRange::describe).
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>

namespace ridge {

// A closed or half-open interval of finite numbers. Infinite ends mean "no bound on that side"
// (the value must still be finite).
struct ValueRange {
    double lo = -std::numeric_limits<double>::infinity();
    double hi = std::numeric_limits<double>::infinity();
    bool lo_open = false; // lo itself excluded
    bool hi_open = false;

    static constexpr ValueRange any() { return {}; }
    static constexpr ValueRange positive() // (0, inf)
    {
        return {0.0, std::numeric_limits<double>::infinity(), true, false};
    }
    static constexpr ValueRange nonNegative() // [0, inf)
    {
        return {0.0, std::numeric_limits<double>::infinity(), false, false};
    }
    static constexpr ValueRange closed(double lo, double hi) { return {lo, hi, false, false}; }
    static constexpr ValueRange openClosed(double lo, double hi) { return {lo, hi, true, false}; }
    static constexpr ValueRange closedOpen(double lo, double hi) { return {lo, hi, false, true}; }

    // True for finite values inside the interval; false for NaN and infinities.
    bool contains(double value) const;
    // "a finite number", "a finite number > 0", "a number in (0, 90]" ...
    std::string describe() const;
};

// A number as messages print it: shortest round-trip form ("0.1", "1e+300", "nan", "inf").
std::string formatNumber(double value);

// Throws ridge::Error("NAME is VALUE: must be RANGE") unless range.contains(value).
void checkParameter(std::string_view name, double value, ValueRange range);
// The same for integers (no NaN, but ranges still matter: sizes, counts).
void checkParameter(std::string_view name, int64_t value, int64_t lo, int64_t hi);
// Each component of a vector of `count` numbers ("camera position is (nan, 0, 0): ...").
void checkParameters(std::string_view name, const double* values, int count, ValueRange range);

} // namespace ridge
