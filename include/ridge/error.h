#pragma once
// The exceptions ridge throws, shared by the public API (<ridge/ridge.h>) and every internal
// layer. Installed with ridge.h. RIDGE_API exports their type information from the shared
// library so that an embedding application catches exactly these types.
#include <stdexcept>
#include <string>

#if defined(_WIN32)
#define RIDGE_API
#else
#define RIDGE_API __attribute__((visibility("default")))
#endif

namespace ridge {

// Any failure a user can cause: bad input, a corrupt archive, an I/O failure, a parameter
// out of range. The message names the file or the parameter and the problem.
class RIDGE_API Error : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

// The operation was cancelled through its progress callback (e.g. Ctrl-C in the CLI).
class RIDGE_API Cancelled : public Error {
  public:
    Cancelled() : Error("cancelled") {}
};

} // namespace ridge
