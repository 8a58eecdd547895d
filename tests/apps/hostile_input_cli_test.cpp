// The command line fed arbitrary bytes (issue 23): paths and stdin are byte strings on POSIX,
// never required to be UTF-8, and input is read in bounded memory. A property test drives
// `ridge` with seeded random byte strings as archive paths, output names and stdin lines; the
// promises hold for each: no signal, no "internal error", exit 0, 1 or 2 only, every --json
// document valid JSON, and every stdin line answered once. CliRun without a shell (fork/exec), so
// that any byte but NUL reaches argv as it is.
#include "test_support.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <poll.h>
#include <random>
#include <sys/resource.h>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

using namespace ridge;
namespace fs = std::filesystem;

namespace {

struct CliRun {
    int exit_code = -1; // the shell's numbering: 128 + N when killed by signal N
    std::string out, err;
    long max_rss_kb = 0;
};

// Runs `ridge ARGS` with `input` on stdin (or the file `stdin_path` when given).
CliRun runBytes(const std::vector<std::string>& args, const std::string& input,
                const std::string& stdin_path = "")
{
    int in[2], out[2], err[2];
    if (::pipe(in) != 0 || ::pipe(out) != 0 || ::pipe(err) != 0)
        throw std::runtime_error("pipe");
    const pid_t pid = ::fork();
    if (pid < 0)
        throw std::runtime_error("fork");
    if (pid == 0) {
        if (stdin_path.empty()) {
            ::dup2(in[0], 0);
        } else {
            const int fd = ::open(stdin_path.c_str(), O_RDONLY);
            ::dup2(fd, 0);
        }
        ::dup2(out[1], 1);
        ::dup2(err[1], 2);
        for (const int fd : {in[0], in[1], out[0], out[1], err[0], err[1]})
            ::close(fd);
        std::vector<std::string> argv = {RIDGE_CLI_PATH};
        argv.insert(argv.end(), args.begin(), args.end());
        std::vector<char*> cargv;
        for (std::string& a : argv)
            cargv.push_back(a.data());
        cargv.push_back(nullptr);
        ::execv(cargv[0], cargv.data());
        ::_exit(127);
    }
    ::close(in[0]);
    ::close(out[1]);
    ::close(err[1]);
    // stdin written by a thread, so that a large input and large outputs cannot deadlock.
    std::thread writer([fd = in[1], &input] {
        size_t at = 0;
        while (at < input.size()) {
            const ssize_t n = ::write(fd, input.data() + at, input.size() - at);
            if (n <= 0)
                break; // the command stopped reading (EPIPE): what it read is what counts
            at += size_t(n);
        }
        ::close(fd);
    });
    CliRun r;
    pollfd fds[2] = {{out[0], POLLIN, 0}, {err[0], POLLIN, 0}};
    int open_fds = 2;
    while (open_fds > 0) {
        if (::poll(fds, 2, -1) < 0)
            break;
        for (int k = 0; k < 2; ++k) {
            if (fds[k].fd < 0 || !(fds[k].revents & (POLLIN | POLLHUP)))
                continue;
            char buf[65536];
            const ssize_t n = ::read(fds[k].fd, buf, sizeof buf);
            if (n <= 0) {
                ::close(fds[k].fd);
                fds[k].fd = -1;
                --open_fds;
            } else {
                (k == 0 ? r.out : r.err).append(buf, size_t(n));
            }
        }
    }
    int status = 0;
    rusage usage{};
    ::wait4(pid, &status, 0, &usage);
    writer.join();
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    r.max_rss_kb = usage.ru_maxrss;
    return r;
}

// The promises every run keeps, whatever its input.
void expectOrderly(const CliRun& r, const std::string& what)
{
    EXPECT_TRUE(r.exit_code == 0 || r.exit_code == 1 || r.exit_code == 2)
        << what << ": exit " << r.exit_code << "\n"
        << r.err;
    EXPECT_EQ(r.err.find("internal error"), std::string::npos) << what << ": " << r.err;
}

// A random byte string of length [1, max]: any byte but NUL (argv cannot hold one), biased
// towards the bytes that break UTF-8 and line handling.
std::string randomBytes(std::mt19937& rng, size_t max, const std::string& forbidden = "")
{
    static const std::string kSpecial = "\xff\xfe\xc3\xa9\xe2\x82\x80\xc0\x80\xed\xa0\x80\r\t "
                                        "\\\"'$`*?[]{}()-,";
    const size_t n = 1 + rng() % max;
    std::string s;
    while (s.size() < n) {
        char c = rng() % 3 == 0 ? kSpecial[rng() % kSpecial.size()] : char(1 + rng() % 255);
        if (forbidden.find(c) == std::string::npos)
            s += c;
    }
    return s;
}

// The lines `query` answers from `input`: split at '\n', one '\r' dropped, lines of only
// blanks and commas skipped (gdallocationinfo's group separators); a line longer than 4096
// bytes counts once.
size_t answeredLines(const std::string& input)
{
    size_t count = 0, start = 0;
    while (start < input.size()) {
        size_t end = input.find('\n', start);
        if (end == std::string::npos)
            end = input.size();
        std::string line = input.substr(start, end - start);
        if (!line.empty() && line.back() == '\r' && line.size() <= 4097)
            line.pop_back();
        if (line.size() > 4096 || line.find_first_not_of(" \t\r,") != std::string::npos)
            ++count;
        start = end + 1;
    }
    return count;
}

struct Fixture {
    test::ScratchDir dir;
    std::string archive = test::buildEverestWithCli(dir, "everest.ridge", "--patch 33");
};

const Fixture& fixture()
{
    static const Fixture f;
    return f;
}

} // namespace

TEST(HostileInputCli, ARasterArchiveAndOutputsNamedWithAnyBytesWorkAndTheirJsonIsValid)
{
    // A raster that is not named in UTF-8 could not be built (type_error.316 writing the
    // metadata), and --json to such a path failed after writing the file.
    test::ScratchDir dir;
    const std::string raster = dir.path("caf\xe9 \xff\xfe.tif");
    fs::copy_file(test::dataPath("everest_crop.tif"), raster);
    const std::string archive = dir.path("\xfe\xff-\xc0\x80.ridge");
    CliRun r = runBytes({"build", raster, "-o", archive, "--patch", "33", "--json"}, "");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    ASSERT_TRUE(nlohmann::json::accept(r.out)) << r.out;
    EXPECT_TRUE(fs::exists(archive));
    r = runBytes({"info", archive, "--json"}, "");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    ASSERT_TRUE(nlohmann::json::accept(r.out)) << r.out;
    // The source path is recorded as UTF-8: its invalid bytes as U+FFFD, the é of UTF-8 kept.
    const nlohmann::json info = nlohmann::json::parse(r.out);
    EXPECT_NE(info["metadata"]["source"]["path"].get<std::string>().find("\xef\xbf\xbd"),
              std::string::npos);
    r = runBytes({"verify", archive, "--json"}, "");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(nlohmann::json::accept(r.out)) << r.out;
    const std::string extracted = dir.path("\xff\xff.tif");
    r = runBytes({"extract", archive, "-o", extracted, "--json"}, "");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(nlohmann::json::accept(r.out)) << r.out;
    EXPECT_TRUE(fs::exists(extracted));
}

TEST(HostileInputCli, OneLineOfBadBytesCostsOnlyItsOwnAnswer)
{
    // A line that was not UTF-8 made `query --json` lose every answer (type_error.316).
    const std::string input = "10 10\n\xff\xfe\x80 junk\n20 20\n";
    const CliRun r = runBytes({"query", fixture().archive, "--pixel", "--json"}, input);
    EXPECT_EQ(r.exit_code, 1) << r.err; // one point without a height
    ASSERT_TRUE(nlohmann::json::accept(r.out)) << r.out;
    const nlohmann::json doc = nlohmann::json::parse(r.out);
    ASSERT_EQ(doc["points"].size(), 3u);
    EXPECT_TRUE(doc["points"][0]["height"].is_number());
    EXPECT_TRUE(doc["points"][1].contains("error"));
    EXPECT_TRUE(doc["points"][2]["height"].is_number());
}

TEST(HostileInputCli, StdinIsReadInBoundedMemoryAndAFailedReadIsAFailure)
{
    // One 256 MB line took about 4 bytes of memory per byte and was echoed back whole: now
    // it is answered as too long, from its first bytes.
    // (From a file written in pieces: the test's own memory would count in the child's peak
    // until it execs.)
    test::ScratchDir dir;
    const std::string input = dir.path("long-line.txt");
    {
        std::ofstream file(input, std::ios::binary);
        const std::string piece(1u << 20, '7');
        for (int k = 0; k < 256; ++k)
            file << piece;
        file << "\n10 10\n";
    }
    const CliRun r = runBytes({"query", fixture().archive, "--pixel"}, "", input);
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_NE(r.out.find("... (line 1 is longer than 4096 bytes): error"), std::string::npos)
        << r.out.substr(0, 300);
    EXPECT_NE(r.out.find("10 10: "), std::string::npos);
    EXPECT_LT(r.out.size(), 1000u);
    // Against the same query of one short line in the same build (a sanitizer build's own
    // baseline sits near 200 MB, and PROJ's database adds to it): the 256 MB line must not
    // add more than a quarter of itself (it cost about four times itself).
    const std::string short_input = dir.path("short.txt");
    std::ofstream(short_input, std::ios::binary) << "10 10\n";
    const CliRun baseline = runBytes({"query", fixture().archive, "--pixel"}, "", short_input);
    ASSERT_EQ(baseline.exit_code, 0) << baseline.err;
    EXPECT_LT(r.max_rss_kb, baseline.max_rss_kb + 64 * 1024)
        << "peak memory, kB (one short line's: " << baseline.max_rss_kb << ")";
    // A directory as stdin ended the input silently: exit 0 and no output.
    const CliRun from_dir =
        runBytes({"query", fixture().archive, "--pixel"}, "", fixture().dir.dir());
    EXPECT_EQ(from_dir.exit_code, 1) << from_dir.err;
    EXPECT_NE(from_dir.err.find("standard input: cannot read: Is a directory"), std::string::npos)
        << from_dir.err;
}

TEST(HostileInputCli, ACameraPathFileWithoutEndIsRefusedAtItsFirstLine)
{
    // `bench --path /dev/zero` grew to 5.6 GB before saying "no camera poses in the file".
    const CliRun r = runBytes(
        {"bench", fixture().archive, "--path", "/dev/zero", "--bytes-per-view", "--frames", "2"},
        "");
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_NE(r.err.find("/dev/zero:1: longer than 4096 bytes: not a camera path file"),
              std::string::npos)
        << r.err;
    // Against the same command on a built-in path, in this build (a sanitizer build's own
    // peak is about 200 MB): reading the file may add little, not gigabytes.
    const CliRun baseline = runBytes(
        {"bench", fixture().archive, "--path", "orbit", "--bytes-per-view", "--frames", "2"}, "");
    ASSERT_EQ(baseline.exit_code, 0) << baseline.err;
    EXPECT_LT(r.max_rss_kb, baseline.max_rss_kb + 64 * 1024)
        << "peak memory, kB (the built-in path's: " << baseline.max_rss_kb << ")";
}

TEST(HostileInputCli, PropertyAnyBytesAsPathsAndStdinGetAnOrderlyAnswer)
{
    std::mt19937 rng(20260523); // fixed: a failure reproduces
    const std::string& archive = fixture().archive;
    test::ScratchDir out;
    for (int round = 0; round < 40; ++round) {
        SCOPED_TRACE("round " + std::to_string(round));
        // An archive path of random bytes (inside the scratch directory, so never a flag):
        // missing, so a failure that names it.
        const std::string missing = out.path(randomBytes(rng, 40, "/"));
        CliRun r = runBytes({"info", missing}, "");
        expectOrderly(r, "info");
        EXPECT_EQ(r.exit_code, 1);
        EXPECT_NE(r.err.find(missing), std::string::npos) << r.err;
        r = runBytes({"verify", missing, "--json"}, "");
        expectOrderly(r, "verify --json");
        EXPECT_TRUE(nlohmann::json::accept(r.out)) << r.out;

        // An output name of random bytes: written there, and its --json is valid.
        const std::string name = randomBytes(rng, 40, "/");
        if (name == "." || name == "..")
            continue;
        r = runBytes(
            {"extract", archive, "-o", out.path(name), "--srcwin", "0", "0", "8", "8", "--json"},
            "");
        expectOrderly(r, "extract");
        EXPECT_EQ(r.exit_code, 0) << r.err;
        EXPECT_TRUE(nlohmann::json::accept(r.out)) << r.out;
        EXPECT_TRUE(fs::exists(out.path(name)));
        fs::remove(out.path(name));

        // stdin of random lines, some long, some numbers: one answer per line, in valid JSON.
        std::string input;
        const int lines = 1 + int(rng() % 12);
        for (int k = 0; k < lines; ++k) {
            switch (rng() % 4) {
            case 0:
                input += std::to_string(rng() % 300) + " " + std::to_string(rng() % 200);
                break;
            case 1:
                input += std::string(4000 + rng() % 200, char('0' + rng() % 10));
                break;
            default:
                input += randomBytes(rng, 60, "\n");
                break;
            }
            input += rng() % 5 == 0 ? "\r\n" : "\n";
        }
        input += std::string(1, char(rng() % 256)) + std::string("\0\0", 2);
        r = runBytes({"query", archive, "--pixel", "--json"}, input);
        expectOrderly(r, "query --json");
        ASSERT_TRUE(nlohmann::json::accept(r.out)) << r.out;
        const nlohmann::json doc = nlohmann::json::parse(r.out);
        EXPECT_EQ(doc["points"].size(), answeredLines(input));
        r = runBytes({"query", archive, "--pixel"}, input);
        expectOrderly(r, "query");
        EXPECT_EQ(size_t(std::count(r.out.begin(), r.out.end(), '\n')), answeredLines(input))
            << r.out;
    }
}
