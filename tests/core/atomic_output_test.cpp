// AtomicOutput: complete files or none, temporaries that cannot be redirected and are
// cleaned up after their owner dies; both the O_TMPFILE path and the named fallback.
#include "ridge/core/atomic_output.h"
#include "ridge/core/error.h"

#include "test_support.h"

#include "error_expectations.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <sys/file.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

using namespace ridge;
namespace fs = std::filesystem;

namespace {

using test::readFile;

using ridge::test::errorOf;

// Forces the named fallback (where O_TMPFILE is missing) for the object's lifetime.
class NamedTemporaries {
  public:
    explicit NamedTemporaries(bool on)
    {
        if (on)
            ::setenv("RIDGE_TEST_NAMED_TEMPORARIES", "1", 1);
        else
            ::unsetenv("RIDGE_TEST_NAMED_TEMPORARIES");
    }
    ~NamedTemporaries() { ::unsetenv("RIDGE_TEST_NAMED_TEMPORARIES"); }
};

std::vector<std::string> entries(const test::ScratchDir& dir)
{
    return test::namesIn(dir.dir());
}

std::vector<std::string> temporaries(const test::ScratchDir& dir, const std::string& final_name)
{
    const std::string prefix = AtomicOutput::temporaryNamePrefix(final_name);
    std::vector<std::string> names;
    for (const std::string& n : entries(dir))
        if (n.rfind(prefix, 0) == 0)
            names.push_back(n);
    return names;
}

void writeAll(int fd, const std::string& text)
{
    ASSERT_EQ(::write(fd, text.data(), text.size()), static_cast<ssize_t>(text.size()));
}

bool tmpfileSupported(const std::string& dir)
{
    const int fd = ::open(dir.c_str(), O_TMPFILE | O_RDWR | O_CLOEXEC, 0600);
    if (fd < 0)
        return false;
    ::close(fd);
    return ::access("/proc/self/fd", X_OK) == 0;
}

class AtomicOutputBothWays : public ::testing::TestWithParam<bool> {};

} // namespace

TEST(AtomicOutput, UsesAnUnnamedTemporaryWhereTheFileSystemHasOTmpfile)
{
    test::ScratchDir dir;
    if (!tmpfileSupported(dir.dir().string()))
        GTEST_SKIP() << "no O_TMPFILE or /proc here; the named fallback is tested below";
    NamedTemporaries off(false);
    AtomicOutput out(dir.path("a.ridge"));
    EXPECT_TRUE(out.unnamed());
    EXPECT_EQ(out.temporaryPath(), "/proc/self/fd/" + std::to_string(out.fd()));
    writeAll(out.fd(), "data");
    EXPECT_TRUE(entries(dir).empty()) << "an unnamed temporary has no directory entry";
}

TEST(AtomicOutput, TheTestHookForcesALockedNamedTemporaryWithAnUnpredictableName)
{
    test::ScratchDir dir;
    NamedTemporaries on(true);
    AtomicOutput a(dir.path("a.ridge"));
    AtomicOutput b(dir.path("a.ridge"));
    EXPECT_FALSE(a.unnamed());
    const std::vector<std::string> names = temporaries(dir, "a.ridge");
    ASSERT_EQ(names.size(), 2u) << "two live outputs, two temporaries, neither removed";
    EXPECT_NE(names[0], names[1]);
    EXPECT_EQ(names[0].size(), std::string(".a.ridge.ridge-tmp-").size() + 16);
    EXPECT_EQ(names[0].find(std::to_string(::getpid())), std::string::npos);
    // Locked by its owner: another open file description cannot take the lock.
    for (const std::string& n : names) {
        const int fd = ::open(dir.path(n).c_str(), O_RDONLY);
        ASSERT_GE(fd, 0);
        EXPECT_NE(::flock(fd, LOCK_EX | LOCK_NB), 0) << n;
        ::close(fd);
    }
}

TEST_P(AtomicOutputBothWays, CommitPublishesTheCompleteFileAndLeavesNoTemporary)
{
    test::ScratchDir dir;
    NamedTemporaries mode(GetParam());
    const std::string path = dir.path("out.ridge");
    {
        AtomicOutput out(path);
        writeAll(out.fd(), "complete");
        EXPECT_FALSE(fs::exists(path)) << "nothing at the final path before commit";
        out.commit();
        EXPECT_EQ(out.fd(), -1);
    }
    EXPECT_EQ(readFile(path), "complete");
    EXPECT_EQ(entries(dir), std::vector<std::string>{"out.ridge"});
    // Permissions as any other new file: 0666 less the umask.
    const mode_t mask = ::umask(0);
    ::umask(mask);
    EXPECT_EQ(fs::status(path).permissions(), fs::perms(0666 & ~mask));
}

TEST_P(AtomicOutputBothWays, AbandoningLeavesNothingAndKeepsThePreviousFile)
{
    test::ScratchDir dir;
    NamedTemporaries mode(GetParam());
    const std::string path = dir.path("out.ridge");
    std::ofstream(path) << "previous";
    {
        AtomicOutput out(path);
        writeAll(out.fd(), "half-written");
    }
    EXPECT_EQ(readFile(path), "previous");
    EXPECT_EQ(entries(dir), std::vector<std::string>{"out.ridge"});
}

TEST_P(AtomicOutputBothWays, LibrariesThatTakeAPathWriteThroughTheMagicLink)
{
    test::ScratchDir dir;
    NamedTemporaries mode(GetParam());
    const std::string path = dir.path("out.png");
    AtomicOutput out(path);
    EXPECT_EQ(out.temporaryPath().rfind("/proc/self/fd/", 0), 0u) << out.temporaryPath();
    // What GDAL and PLplot do: fopen("wb") the path they were given (truncating it).
    std::FILE* f = std::fopen(out.temporaryPath().c_str(), "wb");
    ASSERT_NE(f, nullptr);
    std::fputs("written by a library", f);
    ASSERT_EQ(std::fclose(f), 0);
    out.commit();
    EXPECT_EQ(readFile(path), "written by a library");
}

TEST_P(AtomicOutputBothWays, AFinalPathThatIsASymlinkIsReplacedNotWrittenThrough)
{
    test::ScratchDir dir;
    NamedTemporaries mode(GetParam());
    const std::string victim = dir.path("victim");
    std::ofstream(victim) << "precious";
    const std::string path = dir.path("out.ridge");
    fs::create_symlink(victim, path);
    AtomicOutput out(path);
    writeAll(out.fd(), "new");
    out.commit();
    EXPECT_EQ(readFile(victim), "precious");
    EXPECT_TRUE(fs::is_regular_file(fs::symlink_status(path)));
    EXPECT_EQ(readFile(path), "new");
}

TEST_P(AtomicOutputBothWays, PlantedLinksFifosAndDirectoriesWithTheTemporaryPrefixAreLeftAlone)
{
    test::ScratchDir dir;
    NamedTemporaries mode(GetParam());
    const std::string victim = dir.path("victim");
    std::ofstream(victim) << "precious";
    const std::string prefix = AtomicOutput::temporaryNamePrefix("out.ridge");
    fs::create_symlink(victim, dir.path(prefix + "symlink"));
    ASSERT_EQ(::mkfifo(dir.path(prefix + "fifo").c_str(), 0644), 0);
    fs::create_directory(dir.path(prefix + "dir"));
    {
        AtomicOutput out(dir.path("out.ridge")); // would hang on the FIFO without O_NONBLOCK
        writeAll(out.fd(), "new");
        out.commit();
    }
    EXPECT_EQ(readFile(victim), "precious");
    EXPECT_TRUE(fs::is_symlink(dir.path(prefix + "symlink")));
    EXPECT_TRUE(fs::is_fifo(dir.path(prefix + "fifo")));
    EXPECT_TRUE(fs::is_directory(dir.path(prefix + "dir")));
    EXPECT_EQ(readFile(dir.path("out.ridge")), "new");
}

TEST_P(AtomicOutputBothWays, TheNextOutputRemovesADeadOwnersTemporaryButNeverALiveOnes)
{
    test::ScratchDir dir;
    NamedTemporaries mode(true); // a dead owner leaves a name only in the fallback
    const std::string path = dir.path("out.ridge");
    int ready[2], release[2];
    ASSERT_EQ(::pipe(ready), 0);
    ASSERT_EQ(::pipe(release), 0);
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        AtomicOutput out(path);
        (void)!::write(out.fd(), "partial", 7);
        (void)!::write(ready[1], "x", 1);
        char c;
        (void)!::read(release[0], &c, 1); // until the parent kills it
        ::_exit(0);
    }
    char c;
    ASSERT_EQ(::read(ready[0], &c, 1), 1);
    ASSERT_EQ(temporaries(dir, "out.ridge").size(), 1u);
    {
        NamedTemporaries same_or_unnamed(GetParam());
        AtomicOutput live_owner_check(path);
        EXPECT_EQ(temporaries(dir, "out.ridge").size(), GetParam() ? 2u : 1u)
            << "a live owner's temporary is kept";
    }
    ::kill(child, SIGKILL);
    int status = 0;
    ::waitpid(child, &status, 0);
    ASSERT_TRUE(WIFSIGNALED(status));
    EXPECT_EQ(temporaries(dir, "out.ridge").size(), 1u) << "SIGKILL left the fallback's file";
    {
        NamedTemporaries same_or_unnamed(GetParam());
        AtomicOutput next(path);
        EXPECT_EQ(temporaries(dir, "out.ridge").size(), GetParam() ? 1u : 0u)
            << "the dead owner's temporary is removed; only the new one's own is left";
    }
    EXPECT_TRUE(entries(dir).empty());
    for (int fd : {ready[0], ready[1], release[0], release[1]})
        ::close(fd);
}

INSTANTIATE_TEST_SUITE_P(UnnamedAndNamed, AtomicOutputBothWays, ::testing::Values(false, true),
                         [](const auto& info) { return info.param ? "Named" : "Unnamed"; });

TEST(AtomicOutput, AnEmptyUnlockedTemporaryMayBeBeingCreatedAndIsKeptWhileYoung)
{
    test::ScratchDir dir;
    const std::string prefix = AtomicOutput::temporaryNamePrefix("out.ridge");
    std::ofstream(dir.path(prefix + "0000000000000000"));           // created, not yet locked
    std::ofstream(dir.path(prefix + "1111111111111111")) << "data"; // unlocked with data: dead
    AtomicOutput out(dir.path("out.ridge"));
    EXPECT_TRUE(fs::exists(dir.path(prefix + "0000000000000000")));
    EXPECT_FALSE(fs::exists(dir.path(prefix + "1111111111111111")));
}

TEST(AtomicOutput, TemporariesOfOtherOutputsAreNotTouched)
{
    test::ScratchDir dir;
    const std::string other = dir.path(AtomicOutput::temporaryNamePrefix("b.ridge") + "0123");
    std::ofstream(other) << "data";
    AtomicOutput out(dir.path("a.ridge"));
    EXPECT_TRUE(fs::exists(other));
}

TEST(AtomicOutput, MissingDirectoriesAndDirectoriesAsOutputsAreClearErrors)
{
    test::ScratchDir dir;
    const std::string missing = dir.path("no/such/dir/out.ridge");
    std::string message = errorOf([&] { AtomicOutput out(missing); });
    EXPECT_NE(message.find(missing + ": cannot write"), std::string::npos) << message;
    EXPECT_NE(message.find("No such file or directory"), std::string::npos) << message;

    fs::create_directory(dir.path("adir"));
    message = errorOf([&] { AtomicOutput out(dir.path("adir")); });
    EXPECT_NE(message.find("is a directory"), std::string::npos) << message;
    message = errorOf([&] { AtomicOutput out(dir.path("adir") + "/"); });
    EXPECT_NE(message.find("cannot write"), std::string::npos) << message;
    EXPECT_EQ(entries(dir), std::vector<std::string>{"adir"});
}

TEST(AtomicOutput, CommittingTwiceIsAnError)
{
    test::ScratchDir dir;
    AtomicOutput out(dir.path("x"));
    out.commit();
    EXPECT_NE(errorOf([&] { out.commit(); }), "");
}

TEST(AtomicOutput, LongFileNamesStillFitTheTemporaryName)
{
    test::ScratchDir dir;
    NamedTemporaries on(true);
    const std::string name(250, 'n');
    AtomicOutput out(dir.path(name));
    writeAll(out.fd(), "x");
    out.commit();
    EXPECT_EQ(readFile(dir.path(name)), "x");
}

TEST(CheckOutputWritable, LeavesNothingBehindAndNamesThePathWhenItCannotWrite)
{
    test::ScratchDir dir;
    for (const bool named : {false, true}) {
        NamedTemporaries mode(named);
        checkOutputWritable(dir.path("report.json"));
        EXPECT_TRUE(entries(dir).empty());
    }
    const std::string bad = dir.path("missing/report.json");
    EXPECT_NE(errorOf([&] { checkOutputWritable(bad); }).find(bad + ": cannot write"),
              std::string::npos);
}

TEST(WriteFileAtomically, WritesTheText)
{
    test::ScratchDir dir;
    writeFileAtomically(dir.path("r.json"), "{}\n");
    EXPECT_EQ(readFile(dir.path("r.json")), "{}\n");
    EXPECT_EQ(entries(dir), std::vector<std::string>{"r.json"});
}

// RLIMIT_FSIZE with SIGXFSZ ignored (as the CLI does): the write fails with EFBIG, the error
// names the path and says why, and no temporary file is left. In a child: the limit and the
// signal disposition are process-wide.
TEST(WriteFileAtomically, FailsCleanlyOverTheFileSizeLimit)
{
    for (const bool named : {false, true}) {
        test::ScratchDir dir;
        const std::string path = dir.path("big.json");
        int pipe_fds[2];
        ASSERT_EQ(::pipe(pipe_fds), 0);
        const pid_t child = ::fork();
        ASSERT_GE(child, 0);
        if (child == 0) {
            NamedTemporaries mode(named);
            std::signal(SIGXFSZ, SIG_IGN);
            const rlimit limit{1000, 1000};
            ::setrlimit(RLIMIT_FSIZE, &limit);
            const std::string message =
                errorOf([&] { writeFileAtomically(path, std::string(5000, 'x')); });
            (void)!::write(pipe_fds[1], message.data(), message.size());
            ::_exit(0);
        }
        ::close(pipe_fds[1]);
        std::string message;
        char buf[512];
        for (ssize_t n; (n = ::read(pipe_fds[0], buf, sizeof buf)) > 0;)
            message.append(buf, size_t(n));
        ::close(pipe_fds[0]);
        int status = 0;
        ::waitpid(child, &status, 0);
        EXPECT_TRUE(WIFEXITED(status));
        EXPECT_NE(message.find(path), std::string::npos) << message;
        EXPECT_NE(message.find("File too large"), std::string::npos) << message;
        EXPECT_TRUE(entries(dir).empty()) << "named = " << named;
    }
}

// An output is a regular file or nothing: a FIFO, a device or a socket at the final path (or
// a symlink to one) is never replaced by the rename (as root, `-o /dev/null` replaced
// /dev/null). Refused when the output is made, and again at commit for one that appears
// during the work.
TEST_P(AtomicOutputBothWays, FifosDevicesSocketsAndLinksToThemAreNeverReplaced)
{
    NamedTemporaries mode(GetParam());
    test::ScratchDir dir;
    const std::string fifo = dir.path("fifo");
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    std::string message = errorOf([&] { AtomicOutput out(fifo); });
    EXPECT_NE(message.find(fifo + ": cannot write: it is a FIFO: outputs are written only to "
                                  "regular files"),
              std::string::npos)
        << message;
    EXPECT_TRUE(fs::is_fifo(fifo));

    message = errorOf([&] { AtomicOutput out("/dev/null"); });
    EXPECT_NE(message.find("/dev/null: cannot write: it is a character device"), std::string::npos)
        << message;
    EXPECT_TRUE(fs::is_character_file("/dev/null"));

    const std::string link = dir.path("null-link");
    fs::create_symlink("/dev/null", link);
    message = errorOf([&] { AtomicOutput out(link); });
    EXPECT_NE(message.find("it is a symlink to a character device"), std::string::npos) << message;
    EXPECT_TRUE(fs::is_symlink(link));

    const std::string socket_path = dir.path("sock");
    const int s = ::socket(AF_UNIX, SOCK_STREAM, 0);
    ASSERT_GE(s, 0);
    sockaddr_un address{};
    address.sun_family = AF_UNIX;
    std::snprintf(address.sun_path, sizeof address.sun_path, "%s", socket_path.c_str());
    ASSERT_EQ(::bind(s, reinterpret_cast<const sockaddr*>(&address), sizeof address), 0);
    message = errorOf([&] { AtomicOutput out(socket_path); });
    EXPECT_NE(message.find("it is a socket"), std::string::npos) << message;
    ::close(s);
    EXPECT_TRUE(fs::is_socket(socket_path));

    // Appearing during the work: commit refuses it and leaves it (and no temporary).
    const std::string late = dir.path("late");
    {
        AtomicOutput out(late);
        writeAll(out.fd(), "data");
        ASSERT_EQ(::mkfifo(late.c_str(), 0600), 0);
        message = errorOf([&] { out.commit(); });
    }
    EXPECT_NE(message.find(late + ": cannot write: it is a FIFO"), std::string::npos) << message;
    EXPECT_TRUE(fs::is_fifo(late));
    EXPECT_TRUE(temporaries(dir, "late").empty());
    // A symlink to a regular file is still replaced (not written through), as before.
    std::ofstream(dir.path("target")) << "old";
    fs::create_symlink(dir.path("target"), dir.path("file-link"));
    writeFileAtomically(dir.path("file-link"), "new");
    EXPECT_EQ(readFile(dir.path("target")), "old");
    EXPECT_FALSE(fs::is_symlink(dir.path("file-link")));
}
