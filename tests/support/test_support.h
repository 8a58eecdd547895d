#pragma once
// Shared helpers for ridge's tests: fixture paths, scratch directories, running the CLI.
#include <filesystem>
#include <string>
#include <vector>

namespace ridge::test {

// Path of a file in tests/data.
std::string dataPath(const std::string& name);

// A fresh empty directory under the system temp dir, removed when the object dies.
class ScratchDir {
  public:
    ScratchDir();
    ~ScratchDir();
    std::string path(const std::string& name) const { return (dir_ / name).string(); }
    const std::filesystem::path& dir() const { return dir_; }

  private:
    std::filesystem::path dir_;
};

struct CommandResult {
    int exit_code = -1;
    std::string output; // stdout and stderr together
};

// The whole content of a file (empty when it cannot be read).
std::string readFile(const std::string& path);

// The names of the entries of `dir`, sorted.
std::vector<std::string> namesIn(const std::filesystem::path& dir);

// Names in `dir` that are temporary outputs of any ridge version: ".NAME.ridge-tmp-RANDOM"
// (AtomicOutput's named fallback) and "NAME.tmp.PID" (before it). Empty when none is left.
std::vector<std::string> temporariesIn(const std::filesystem::path& dir);

// Runs a shell command line and captures stdout and stderr together.
CommandResult runShell(const std::string& command);

// Runs the `ridge` command line with `args` (already shell-quoted) and captures its output.
// Only in test binaries declared NEEDS_CLI.
CommandResult runRidge(const std::string& args);

// Runs `ridge ARGS` and captures its stdout alone (stderr is discarded): for the documents
// `--json` prints there. Only in test binaries declared NEEDS_CLI.
CommandResult runRidgeStdout(const std::string& args);

// `ridge build` of the Everest fixture (tests/data/everest_crop.tif) into `dir`/`name` with
// the extra build arguments `args`; returns the archive's path. Throws (failing the calling
// test) with the command's output when the build fails. NEEDS_CLI, as runRidge.
std::string buildEverestWithCli(const ScratchDir& dir, const std::string& name,
                                const std::string& args);
// The same for any fixture of tests/data (`data_file`, e.g. "etopo5_globe_181x91.tif").
std::string buildWithCli(const ScratchDir& dir, const std::string& data_file,
                         const std::string& name, const std::string& args);

} // namespace ridge::test
