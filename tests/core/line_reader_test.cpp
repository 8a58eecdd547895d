// LineReader: lines in bounded memory whatever the input (one endless line, /dev/zero, a
// directory as stdin, a failing read), as bytes; and jsonText, which emits any bytes as JSON.
#include "ridge/core/json_text.h"
#include "ridge/core/line_reader.h"

#include "error_expectations.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <fcntl.h>
#include <fstream>
#include <sys/wait.h>
#include <unistd.h>

using namespace ridge;
using test::errorOf;

namespace {

// All lines of `text` read through a pipe with lines of at most `max` bytes.
std::vector<LineReader::Line> linesOf(const std::string& text, size_t max,
                                      uint64_t total = LineReader::kUnlimited)
{
    int fds[2];
    EXPECT_EQ(::pipe(fds), 0);
    std::vector<LineReader::Line> out;
    // Written from a child so that texts larger than the pipe's buffer do not block.
    const pid_t child = ::fork();
    if (child == 0) {
        ::close(fds[0]);
        size_t at = 0;
        while (at < text.size()) {
            const ssize_t n = ::write(fds[1], text.data() + at, text.size() - at);
            if (n <= 0)
                ::_exit(1);
            at += size_t(n);
        }
        ::_exit(0);
    }
    ::close(fds[1]);
    LineReader reader(fds[0], "test input", max, total);
    while (std::optional<LineReader::Line> line = reader.next())
        out.push_back(*line);
    ::close(fds[0]);
    ::waitpid(child, nullptr, 0);
    return out;
}

} // namespace

TEST(LineReader, SplitsLinesDropsCarriageReturnsAndKeepsAnyBytes)
{
    const std::string bytes("a b\r\n\xff\xfe\0z\n\nlast", 15);
    const std::vector<LineReader::Line> lines = linesOf(bytes, 100);
    ASSERT_EQ(lines.size(), 4u);
    EXPECT_EQ(lines[0].text, "a b");
    EXPECT_EQ(lines[1].text, std::string("\xff\xfe\0z", 4));
    EXPECT_EQ(lines[2].text, "");
    EXPECT_EQ(lines[3].text, "last"); // no final newline
    EXPECT_EQ(lines[3].number, 4);
    for (const LineReader::Line& l : lines)
        EXPECT_FALSE(l.too_long);
}

TEST(LineReader, ALongLineIsReportedWithItsStartAndNeverStoredWhole)
{
    // 10 MB on one line, then a short one: the long one comes back cut to the limit and
    // flagged, and the next line is intact.
    const std::string long_line(10u << 20, 'x');
    const std::vector<LineReader::Line> lines = linesOf(long_line + "\n1 2\n", 4096);
    ASSERT_EQ(lines.size(), 2u);
    EXPECT_TRUE(lines[0].too_long);
    EXPECT_EQ(lines[0].text.size(), 4096u);
    EXPECT_LT(lines[0].text.capacity(), 65536u);
    EXPECT_EQ(lines[1].text, "1 2");
    EXPECT_FALSE(lines[1].too_long);
    // Exactly at the limit is not too long; one byte more is. A '\r' does not count.
    EXPECT_FALSE(linesOf(std::string(8, 'y') + "\r\n", 8)[0].too_long);
    EXPECT_TRUE(linesOf(std::string(9, 'y') + "\n", 8)[0].too_long);
}

TEST(LineReader, AnEndlessInputIsBoundedByTheTotalLimit)
{
    // /dev/zero: one line without end. It is too long as soon as 4096 bytes are in, and a
    // caller that reads on is stopped by the total limit.
    LineReader zero("/dev/zero", 4096, 1u << 20);
    const std::optional<LineReader::Line> first = zero.next();
    ASSERT_TRUE(first.has_value());
    EXPECT_TRUE(first->too_long);
    const std::string message = errorOf([&] { zero.next(); });
    EXPECT_NE(message.find("/dev/zero: more than 1048576 bytes"), std::string::npos) << message;
}

TEST(LineReader, ReadErrorsAndDirectoriesAreErrorsNotAnEmptyInput)
{
    // std::getline on a directory as stdin just ended: `query` printed nothing and said OK.
    test::ScratchDir dir;
    const int fd = ::open(dir.dir().c_str(), O_RDONLY | O_DIRECTORY);
    ASSERT_GE(fd, 0);
    LineReader reader(fd, "standard input", 100);
    std::string message = errorOf([&] { reader.next(); });
    EXPECT_EQ(message, "standard input: cannot read: Is a directory");
    ::close(fd);
    message = errorOf([&] { LineReader missing(dir.path("missing"), 100); });
    EXPECT_NE(message.find(dir.path("missing") + ": cannot open: No such file or directory"),
              std::string::npos)
        << message;
}

TEST(JsonText, AnyBytesInStringsAreEmittedInsteadOfThrowing)
{
    // nlohmann's dump throws type_error.316 on invalid UTF-8 (a path, a stdin line):
    // jsonText replaces those bytes by U+FFFD and keeps every valid character.
    const nlohmann::json j = {{"path", std::string("caf\xc3\xa9-\xff\xfe.tif")}, {"n", 1}};
    EXPECT_THROW((void)j.dump(), nlohmann::json::type_error);
    const std::string text = jsonText(j, -1);
    EXPECT_EQ(text, "{\"n\":1,\"path\":\"caf\xc3\xa9-\xef\xbf\xbd\xef\xbf\xbd.tif\"}");
    EXPECT_TRUE(nlohmann::json::accept(text));
}
