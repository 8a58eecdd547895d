#pragma once
// An output file that appears at its final path only when it is complete.
//
// Writers write to temporaryPath() (same directory, so rename is atomic on POSIX file
// systems) and call commit(). If the object is destroyed without commit() — an exception,
// a cancelled build — the temporary file is removed and nothing is left at the final path.
// A process killed outright (SIGKILL) may leave "<path>.tmp.<pid>" behind, never a partial
// file at <path>.
#include <string>

namespace ridge {

class AtomicOutput {
  public:
    explicit AtomicOutput(std::string final_path);
    ~AtomicOutput();
    AtomicOutput(const AtomicOutput&) = delete;
    AtomicOutput& operator=(const AtomicOutput&) = delete;

    const std::string& temporaryPath() const { return temp_path_; }
    const std::string& finalPath() const { return final_path_; }

    // fsyncs the temporary file and renames it over the final path. Throws Error on failure.
    void commit();

  private:
    std::string final_path_;
    std::string temp_path_;
    bool committed_ = false;
};

// Throws Error("PATH: cannot write: REASON") when a file cannot be created at `path` (its
// directory is missing or read-only), leaving nothing behind: for commands to check their
// outputs before long work rather than after it.
void checkOutputWritable(const std::string& path);

// Writes `text` to `path` through an AtomicOutput (reports, JSON). Throws Error naming the
// path when it cannot be written.
void writeFileAtomically(const std::string& path, const std::string& text);

} // namespace ridge
