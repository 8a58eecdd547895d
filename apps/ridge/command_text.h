#pragma once
// Small pieces of wording the subcommands share: the quiet flag, byte counts and lengths as a
// person reads them.
#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include <cmath>
#include <cstdint>
#include <string>

namespace ridge::cli {

inline void addCommonFlags(CLI::App* cmd, bool& quiet)
{
    cmd->add_flag("-q,--quiet", quiet, "No progress output");
}

// "74.5 KiB", "812 B".
inline std::string humanBytes(uint64_t bytes)
{
    const char* units[] = {"B", "KiB", "MiB", "GiB", "TiB"};
    double v = double(bytes);
    int u = 0;
    while (v >= 1024.0 && u < 4) {
        v /= 1024.0;
        ++u;
    }
    return u == 0 ? fmt::format("{} B", bytes) : fmt::format("{:.1f} {}", v, units[u]);
}

// A length in metres with three significant digits, in mm below a metre: "1.78 mm", "0.5 m"
// would read "500 mm"; "2 m", "0 m".
inline std::string humanMetres(double metres)
{
    if (metres == 0.0 || !std::isfinite(metres))
        return fmt::format("{:g} m", metres);
    return std::abs(metres) < 1.0 ? fmt::format("{:.3g} mm", metres * 1000.0)
                                  : fmt::format("{:.3g} m", metres);
}

} // namespace ridge::cli
