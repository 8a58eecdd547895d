#pragma once
// What main() says about a command line CLI11 refused: the unknown command or flag by name,
// with the nearest valid one ("did you mean"), else CLI11's own message.
#include <CLI/CLI.hpp>

#include <string>
#include <vector>

namespace ridge::cli {

// The message for a ParseError `error` of `app` on the arguments `args` (argv[1..]).
std::string describeUsageError(CLI::App& app, const std::vector<std::string>& args,
                               const CLI::ParseError& error);

// Appends, for each library parameter named in `message` (e.g. "max_error"), the flag that
// sets it ("max_error is --max-error"): library errors speak of parameters, not flags.
std::string withFlagNames(const std::string& message);

} // namespace ridge::cli
