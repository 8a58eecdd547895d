#pragma once
// Lines from a file or a stream (stdin, a FIFO, /dev/zero) in bounded memory, as bytes.
//
// std::getline stores a line whatever its length (one 100 MB line took 434 MB and was echoed
// back) and std::cin turns a read error, or a directory as stdin, into a silent end of input.
// Here a line is at most `max_line_bytes` long: longer ones are reported as too long with their
// first bytes as soon as the limit is passed, and the rest of them is read and dropped by the
// next call, without being stored; the whole input
// may be limited too; and a failed read is an Error naming the input. Lines are byte strings
// (no encoding is assumed or checked): a NUL or invalid UTF-8 is the caller's to judge.
//
// Not thread-safe: one reader, one thread.
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace ridge {

class LineReader {
  public:
    static constexpr uint64_t kUnlimited = std::numeric_limits<uint64_t>::max();

    // Reads from `fd` (not owned; 0 for stdin), called `name` in messages ("standard input").
    LineReader(int fd, std::string name, size_t max_line_bytes,
               uint64_t max_total_bytes = kUnlimited);
    // Opens `path` (owned, closed by the destructor); throws Error("PATH: cannot open: REASON").
    LineReader(const std::string& path, size_t max_line_bytes,
               uint64_t max_total_bytes = kUnlimited);
    ~LineReader();
    LineReader(const LineReader&) = delete;
    LineReader& operator=(const LineReader&) = delete;

    struct Line {
        std::string text;      // without its '\n' (and a '\r' before it); at most max_line_bytes
        int64_t number = 0;    // 1 for the first line
        bool too_long = false; // the line was longer: `text` holds its first max_line_bytes
    };

    // The next line, or nullopt at the end of the input (a last line without '\n' counts).
    // Throws Error("NAME: cannot read: REASON") when a read fails (a directory: "Is a
    // directory"), and Error("NAME: more than N bytes: ...") past max_total_bytes.
    std::optional<Line> next();

    const std::string& name() const { return name_; }
    size_t maxLineBytes() const { return max_line_; }

  private:
    // Refills the buffer; false at the end of the input.
    bool fill();

    int fd_ = -1;
    bool owned_ = false;
    std::string name_;
    size_t max_line_ = 0;
    uint64_t max_total_ = kUnlimited;
    uint64_t total_ = 0;
    std::vector<char> buffer_;
    size_t begin_ = 0, end_ = 0;
    bool eof_ = false;
    bool skipping_ = false; // inside a too-long line already returned
    int64_t number_ = 0;
};

} // namespace ridge
