#pragma once
// The command line itself is wrong: an unknown command or flag, a missing or malformed
// argument, a value outside its flag's range. main() prints the message and exits with
// status 2 (usage), where failures while running (files, archives, GDAL) exit with 1.
#include "ridge/core/error.h"

namespace ridge::cli {

class UsageError : public Error {
  public:
    using Error::Error;
};

// Exit statuses, as README.md documents them. An interrupt (SIGINT, SIGTERM, SIGHUP) ends
// the process by that signal instead (the shell reports 128 + its number).
constexpr int kExitSuccess = 0;
constexpr int kExitFailure = 1;
constexpr int kExitUsage = 2;

} // namespace ridge::cli
