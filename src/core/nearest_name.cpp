#include "ridge/core/nearest_name.h"

#include <algorithm>
#include <cctype>

namespace ridge {

namespace {

char lower(char c)
{
    return char(std::tolower(static_cast<unsigned char>(c)));
}

} // namespace

std::size_t editDistance(std::string_view a, std::string_view b)
{
    // Three rows of the dynamic-programming table: a transposition looks two rows back.
    const std::size_t n = b.size();
    std::vector<std::size_t> before(n + 1), previous(n + 1), current(n + 1);
    for (std::size_t j = 0; j <= n; ++j)
        previous[j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i) {
        current[0] = i;
        for (std::size_t j = 1; j <= n; ++j) {
            const std::size_t substitution = a[i - 1] == b[j - 1] ? 0 : 1;
            current[j] =
                std::min({previous[j] + 1, current[j - 1] + 1, previous[j - 1] + substitution});
            if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
                current[j] = std::min(current[j], before[j - 2] + 1);
        }
        std::swap(before, previous);
        std::swap(previous, current);
    }
    return previous[n];
}

std::optional<std::string> nearestName(std::string_view name,
                                       const std::vector<std::string>& candidates)
{
    std::string folded(name);
    std::transform(folded.begin(), folded.end(), folded.begin(), lower);
    const std::size_t allowed =
        std::min(1 + folded.size() / 4, folded.size() - (folded.empty() ? 0 : 1));
    std::optional<std::string> best;
    std::size_t best_distance = allowed + 1;
    for (const std::string& candidate : candidates) {
        std::string c = candidate;
        std::transform(c.begin(), c.end(), c.begin(), lower);
        const std::size_t d = editDistance(folded, c);
        if (d < best_distance) {
            best_distance = d;
            best = candidate;
        }
    }
    return best;
}

} // namespace ridge
