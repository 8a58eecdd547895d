#pragma once
// Error reporting for the high-level layers (ingest, archive, pipeline).
//
// Hot or fuzzed code (codecs, block parsing) returns error codes instead; the layers above
// turn those into an Error whose message names the file and the problem, which the command
// line prints verbatim before exiting non-zero.
#include <stdexcept>
#include <string>

namespace ridge {

// Any failure a user can cause: bad input, corrupt archive, I/O failure.
class Error : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// The operation was cancelled through its progress callback (e.g. Ctrl-C in the CLI).
class Cancelled : public Error {
public:
    Cancelled() : Error("cancelled") {}
};

} // namespace ridge
