#include "ridge/core/line_reader.h"

#include "ridge/core/error.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <unistd.h>

namespace ridge {

namespace {

constexpr size_t kBufferBytes = 64 * 1024;

} // namespace

LineReader::LineReader(int fd, std::string name, size_t max_line_bytes, uint64_t max_total_bytes)
    : fd_(fd), name_(std::move(name)), max_line_(std::max<size_t>(1, max_line_bytes)),
      max_total_(max_total_bytes), buffer_(kBufferBytes)
{
}

LineReader::LineReader(const std::string& path, size_t max_line_bytes, uint64_t max_total_bytes)
    : LineReader(::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NOCTTY), path, max_line_bytes,
                 max_total_bytes)
{
    if (fd_ < 0)
        throw Error(path + ": cannot open: " + std::strerror(errno));
    owned_ = true;
}

LineReader::~LineReader()
{
    if (owned_ && fd_ >= 0)
        ::close(fd_);
}

bool LineReader::fill()
{
    if (eof_)
        return false;
    begin_ = end_ = 0;
    while (true) {
        const ssize_t n = ::read(fd_, buffer_.data(), buffer_.size());
        if (n < 0 && errno == EINTR)
            continue;
        if (n < 0)
            throw Error(name_ + ": cannot read: " + std::strerror(errno));
        if (n == 0) {
            eof_ = true;
            return false;
        }
        total_ += static_cast<uint64_t>(n);
        if (total_ > max_total_)
            throw Error(name_ + ": more than " + std::to_string(max_total_) +
                        " bytes: too long for what it should hold");
        end_ = static_cast<size_t>(n);
        return true;
    }
}

std::optional<LineReader::Line> LineReader::next()
{
    // The rest of the previous line, which was too long: read and dropped.
    while (skipping_) {
        if (begin_ == end_ && !fill())
            return std::nullopt;
        const char* start = buffer_.data() + begin_;
        const char* newline = static_cast<const char*>(std::memchr(start, '\n', end_ - begin_));
        begin_ = newline ? static_cast<size_t>(newline - buffer_.data()) + 1 : end_;
        skipping_ = newline == nullptr;
    }
    Line line;
    bool any = false; // a byte or a newline was read for this line
    while (true) {
        if (begin_ == end_ && !fill())
            break;
        any = true;
        const char* start = buffer_.data() + begin_;
        const char* newline = static_cast<const char*>(std::memchr(start, '\n', end_ - begin_));
        const size_t take = newline ? static_cast<size_t>(newline - start) : end_ - begin_;
        // Keep one byte past the limit so that a '\r' before the '\n' can still be dropped.
        const size_t room = max_line_ + 1 - std::min(line.text.size(), max_line_ + 1);
        line.text.append(start, std::min(take, room));
        if (take > room) {
            // Said at once, without reading the rest first (which may never end): the next
            // call drops it.
            line.too_long = true;
            begin_ += take;
            if (newline)
                ++begin_;
            else
                skipping_ = true;
            break;
        }
        begin_ += take;
        if (newline) {
            ++begin_;
            break;
        }
    }
    if (!any)
        return std::nullopt;
    if (!line.text.empty() && line.text.back() == '\r' && !line.too_long)
        line.text.pop_back();
    if (line.text.size() > max_line_) {
        line.text.resize(max_line_);
        line.too_long = true;
    }
    line.number = ++number_;
    return line;
}

} // namespace ridge
