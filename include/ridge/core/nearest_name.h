#pragma once
// "Did you mean": the known name nearest to a mistyped one (subcommands, flags, GDAL drivers).
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace ridge {

// Levenshtein distance with adjacent transpositions counted as one edit (the "optimal string
// alignment" distance): insertions, deletions, substitutions and swaps of two neighbouring
// characters, each 1. "biuld" -> "build" is 1, "frams" -> "frames" is 1. O(|a| |b|).
std::size_t editDistance(std::string_view a, std::string_view b);

// The candidate nearest to `name` when it is close enough to be a typo of it: at most
// 1 + |name| / 4 edits and fewer edits than `name` has characters (so "x" suggests nothing).
// Ties go to the earlier candidate. Comparison ignores ASCII case ("GTIFF" -> "GTiff").
std::optional<std::string> nearestName(std::string_view name,
                                       const std::vector<std::string>& candidates);

} // namespace ridge
