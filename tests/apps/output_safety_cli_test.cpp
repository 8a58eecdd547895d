// Output safety of the `ridge` command line, as an attacker, a careless user or a killed job
// would test it: no output replaces an input whatever path names it; temporary files are
// never reached through planted symlinks and do not outlive the process (SIGKILL, SIGTERM,
// SIGHUP, a file-size limit); unwritable outputs are clear errors.
//
// The CLI is run with fork/exec (not a shell) so that each test knows the child's pid before
// it runs (to plant symlinks at names derived from it) and can stop, signal and limit it.
// RIDGE_TEST_CLI=/path/to/ridge runs these tests against another build of the CLI (to show
// that they fail on an older one). Also: outputs never replace a FIFO, device or socket, and a
// failed write to stdout is a failure (issue 23).
#include "test_support.h"

#include <gdal.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <poll.h>
#include <sstream>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

using namespace ridge;
namespace fs = std::filesystem;

namespace {

using test::readFile;

std::string cliPath()
{
    const char* other = std::getenv("RIDGE_TEST_CLI");
    return other && *other ? other : RIDGE_CLI_PATH;
}

struct SpawnOptions {
    std::string cwd;                                      // empty: the test's
    std::vector<std::pair<std::string, std::string>> env; // added to the environment
    std::optional<rlim_t> file_size_limit;                // RLIMIT_FSIZE, bytes
    std::vector<std::string> prefix;                      // a wrapper command (setpriv)
    bool ignore_sighup = false;                           // as under nohup
    std::function<void(pid_t)> before_exec;               // runs in the parent, child waits
};

// A running `ridge`: stdout and stderr through one pipe.
class Ridge {
  public:
    Ridge(const std::vector<std::string>& args, const SpawnOptions& options = {})
    {
        int out[2], go[2];
        if (::pipe(out) != 0 || ::pipe(go) != 0)
            throw std::runtime_error("pipe");
        std::vector<std::string> argv = options.prefix;
        argv.push_back(cliPath());
        argv.insert(argv.end(), args.begin(), args.end());
        pid_ = ::fork();
        if (pid_ < 0)
            throw std::runtime_error("fork");
        if (pid_ == 0) {
            ::dup2(out[1], 1);
            ::dup2(out[1], 2);
            ::close(out[0]);
            ::close(go[1]);
            char c;
            if (::read(go[0], &c, 1) != 1) // until the parent has planted what it plants
                ::_exit(126);
            // A foreground command's signals, whatever the test runner ignores or blocks.
            for (const int s : {SIGINT, SIGTERM, SIGHUP, SIGXFSZ})
                std::signal(s, SIG_DFL);
            if (options.ignore_sighup)
                std::signal(SIGHUP, SIG_IGN);
            sigset_t none;
            sigemptyset(&none);
            ::sigprocmask(SIG_SETMASK, &none, nullptr);
            if (!options.cwd.empty() && ::chdir(options.cwd.c_str()) != 0)
                ::_exit(126);
            for (const auto& [k, v] : options.env)
                ::setenv(k.c_str(), v.c_str(), 1);
            if (options.file_size_limit) {
                const rlimit limit{*options.file_size_limit, *options.file_size_limit};
                ::setrlimit(RLIMIT_FSIZE, &limit);
            }
            std::vector<char*> cargv;
            for (std::string& a : argv)
                cargv.push_back(a.data());
            cargv.push_back(nullptr);
            ::execvp(cargv[0], cargv.data());
            ::_exit(127);
        }
        ::close(out[1]);
        ::close(go[0]);
        out_ = out[0];
        if (options.before_exec)
            options.before_exec(pid_);
        (void)!::write(go[1], "g", 1);
        ::close(go[1]);
    }
    ~Ridge()
    {
        if (pid_ > 0 && !reaped_) {
            ::kill(pid_, SIGKILL);
            ::waitpid(pid_, nullptr, 0);
        }
        if (out_ >= 0)
            ::close(out_);
    }

    pid_t pid() const { return pid_; }
    const std::string& output() const { return output_; }

    // Reads the output until it contains `needle` (true) or the child closes it / 120 s pass.
    bool waitFor(const std::string& needle)
    {
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
        while (output_.find(needle) == std::string::npos)
            if (std::chrono::steady_clock::now() > deadline || readSome(1000) < 0)
                return false;
        return true;
    }

    // Waits for the exit; the shell's numbering: the exit code, or 128 + N when killed by N.
    int finish()
    {
        while (readSome(-1) >= 0) {
        }
        int status = 0;
        ::waitpid(pid_, &status, 0);
        reaped_ = true;
        signalled_ = WIFSIGNALED(status);
        return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    }
    bool signalled() const { return signalled_; }

  private:
    // 1: read some output, 0: none within `timeout_ms` (-1: no limit), -1: the output ended.
    int readSome(int timeout_ms)
    {
        pollfd p{out_, POLLIN, 0};
        const int ready = ::poll(&p, 1, timeout_ms);
        if (ready <= 0)
            return ready == 0 || errno == EINTR ? 0 : -1;
        char buf[4096];
        const ssize_t n = ::read(out_, buf, sizeof buf);
        if (n <= 0)
            return -1;
        output_.append(buf, size_t(n));
        return 1;
    }

    pid_t pid_ = -1;
    int out_ = -1;
    std::string output_;
    bool reaped_ = false;
    bool signalled_ = false;
};

struct CliResult {
    int exit_code;
    std::string output;
};

CliResult runCli(const std::vector<std::string>& args, const SpawnOptions& options = {})
{
    Ridge r(args, options);
    const int code = r.finish();
    return {code, r.output()};
}

// Every name in `dir` but `keep`: leftovers (temporaries of any naming scheme).
std::vector<std::string> othersIn(const fs::path& dir, const std::vector<std::string>& keep)
{
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir)) {
        const std::string n = e.path().filename().string();
        if (std::find(keep.begin(), keep.end(), n) == keep.end())
            names.push_back(n);
    }
    return names;
}

std::string everestCopy(const test::ScratchDir& dir, const std::string& name = "d.tif")
{
    fs::copy_file(test::dataPath("everest_crop.tif"), dir.path(name));
    return dir.path(name);
}

std::string everestArchive(const test::ScratchDir& dir)
{
    const std::string arc = dir.path("a.ridge");
    const CliResult r = runCli({"build", test::dataPath("everest_crop.tif"), "-o", arc, "-q"});
    if (r.exit_code != 0)
        throw std::runtime_error("build failed: " + r.output);
    return arc;
}

// The ways of naming `file` that are not its own path: ./-prefixed (relative, run in its
// directory), dir/./name, a symlink and a hard link (both created in `dir`).
struct OtherName {
    std::string path;
    std::string cwd;
};
std::vector<OtherName> otherNamesOf(const test::ScratchDir& dir, const std::string& file)
{
    const std::string name = fs::path(file).filename().string();
    fs::create_symlink(file, dir.path("symlink-to-" + name));
    fs::create_hard_link(file, dir.path("hardlink-to-" + name));
    return {{file, ""},
            {"./" + name, dir.dir().string()},
            {(dir.dir() / "." / name).string(), ""},
            {dir.path("symlink-to-" + name), ""},
            {dir.path("hardlink-to-" + name), ""}};
}

void expectRefused(const CliResult& r, const std::string& output, const std::string& input)
{
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_NE(r.output.find(output + ":"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(input), std::string::npos) << "names the input: " << r.output;
    EXPECT_NE(r.output.find("same file"), std::string::npos) << r.output;
}

// A raster big enough that a build takes seconds and reports progress many times: 4097²
// Int16 (32 MB), rough enough that the lossless codec has work to do. Made once.
const std::string& bigRaster()
{
    static const test::ScratchDir dir;
    static const std::string path = [] {
        const std::string p = dir.path("big.tif");
        const int n = 4097;
        GDALAllRegister();
        GDALDatasetH ds =
            GDALCreate(GDALGetDriverByName("GTiff"), p.c_str(), n, n, 1, GDT_Int16, nullptr);
        if (!ds)
            throw std::runtime_error("cannot create " + p);
        std::vector<int16_t> row(n);
        uint32_t state = 12345;
        for (int y = 0; y < n; ++y) {
            for (int x = 0; x < n; ++x) {
                state = state * 1664525u + 1013904223u;
                row[x] = int16_t(2000 + 800 * std::sin(x / 97.0) * std::cos(y / 131.0) +
                                 int(state >> 26));
            }
            if (GDALRasterIO(GDALGetRasterBand(ds, 1), GF_Write, 0, y, n, 1, row.data(), n, 1,
                             GDT_Int16, 0, 0) != CE_None)
                throw std::runtime_error("cannot write " + p);
        }
        GDALClose(ds);
        return p;
    }();
    return path;
}

// "/proc/PID/fd" has a descriptor of a deleted (unnamed, O_TMPFILE) file in `dir`.
bool holdsUnnamedFileIn(pid_t pid, const fs::path& dir)
{
    std::error_code ec;
    for (const auto& e : fs::directory_iterator("/proc/" + std::to_string(pid) + "/fd", ec)) {
        const std::string target = fs::read_symlink(e.path(), ec).string();
        if (target.rfind(dir.string() + "/", 0) == 0 &&
            target.find("(deleted)") != std::string::npos)
            return true;
    }
    return false;
}

const std::vector<std::pair<std::string, std::string>> kNamedTemporaries{
    {"RIDGE_TEST_NAMED_TEMPORARIES", "1"}};

// Starts a build of the big raster into `out_dir`/out.ridge and stops it (SIGSTOP) once it
// has reported 10%: mid-build, its temporary file exists.
std::unique_ptr<Ridge> stoppedMidBuild(const fs::path& out_dir, bool named)
{
    SpawnOptions o;
    if (named)
        o.env = kNamedTemporaries;
    auto r = std::make_unique<Ridge>(
        std::vector<std::string>{"build", bigRaster(), "-o", (out_dir / "out.ridge").string()}, o);
    EXPECT_TRUE(r->waitFor("10")) << r->output();
    ::kill(r->pid(), SIGSTOP);
    if (named)
        EXPECT_EQ(othersIn(out_dir, {}).size(), 1u) << "the named temporary exists mid-build";
    else
        EXPECT_TRUE(holdsUnnamedFileIn(r->pid(), out_dir)) << "an O_TMPFILE file mid-build";
    return r;
}

class OutputSafetyTemporaries : public ::testing::TestWithParam<bool> {};

std::string modeName(const ::testing::TestParamInfo<bool>& info)
{
    return info.param ? "NamedFallback" : "Unnamed";
}

} // namespace

// --- No output replaces an input -----------------------------------------------------------

TEST(OutputSafety, BuildRefusesAnOutputThatIsItsInputByAnyPathAndLeavesTheInputUntouched)
{
    test::ScratchDir dir;
    const std::string input = everestCopy(dir);
    const std::string before = readFile(input);
    for (const OtherName& out : otherNamesOf(dir, input)) {
        SpawnOptions o;
        o.cwd = out.cwd;
        expectRefused(runCli({"build", input, "-o", out.path, "-q"}, o), out.path, input);
        EXPECT_TRUE(readFile(input) == before) << "the input was changed by -o " << out.path;
    }
    EXPECT_EQ(othersIn(dir.dir(), {"d.tif", "symlink-to-d.tif", "hardlink-to-d.tif"}),
              std::vector<std::string>{});
}

TEST(OutputSafety, BuildRefusesAnOutputThatReachesItsInputThroughABindMount)
{
    test::ScratchDir dir;
    fs::create_directory(dir.path("a"));
    fs::create_directory(dir.path("b"));
    const std::string input = everestCopy(dir, "a/d.tif");
    const std::string before = readFile(input);
    // A private mount namespace, so that the bind mount is the child's alone.
    if (test::runShell("unshare -m mount --bind '" + dir.path("a") + "' '" + dir.path("b") + "'")
            .exit_code != 0)
        GTEST_SKIP() << "no bind mounts here (unshare -m and mount need CAP_SYS_ADMIN)";
    SpawnOptions o;
    o.prefix = {"unshare",
                "-m",
                "sh",
                "-c",
                "mount --bind \"$1\" \"$2\" && shift 2 && exec \"$@\"",
                "sh",
                dir.path("a"),
                dir.path("b")};
    const std::string out = dir.path("b/d.tif");
    expectRefused(runCli({"build", input, "-o", out, "-q"}, o), out, input);
    EXPECT_TRUE(readFile(input) == before) << "the input was changed";
}

TEST(OutputSafety, BuildRefusesToReplaceASideCarFileThatGdalReadsWithTheRaster)
{
    // ENVI: the samples in .bil, the geometry in .hdr; GDALGetFileList lists both.
    test::ScratchDir dir;
    const std::string bil = dir.path("d.bil"), hdr = dir.path("d.hdr");
    GDALAllRegister();
    GDALDatasetH src = GDALOpen(test::dataPath("everest_crop.tif").c_str(), GA_ReadOnly);
    ASSERT_NE(src, nullptr);
    GDALDatasetH envi = GDALCreateCopy(GDALGetDriverByName("ENVI"), bil.c_str(), src, FALSE,
                                       nullptr, nullptr, nullptr);
    ASSERT_NE(envi, nullptr);
    GDALClose(envi);
    GDALClose(src);
    ASSERT_TRUE(fs::exists(hdr));
    const std::string before = readFile(hdr);
    expectRefused(runCli({"build", bil, "-o", hdr, "-q"}), hdr, hdr);
    EXPECT_TRUE(readFile(hdr) == before) << "the .hdr was changed";
}

TEST(OutputSafety, ExtractHillshadeAndRenderRefuseToReplaceTheArchiveByAnyPath)
{
    test::ScratchDir dir;
    const std::string arc = everestArchive(dir);
    const std::string before = readFile(arc);
    for (const OtherName& out : otherNamesOf(dir, arc))
        for (const std::vector<std::string>& command :
             {std::vector<std::string>{"extract", arc, "-q"},
              {"hillshade", arc, "-q"},
              {"render", arc, "--size", "32x32"}}) {
            std::vector<std::string> args = command;
            args.insert(args.end(), {"-o", out.path});
            SpawnOptions o;
            o.cwd = out.cwd;
            expectRefused(runCli(args, o), out.path, arc);
            EXPECT_TRUE(readFile(arc) == before)
                << "the archive was changed by " << command[0] << " -o " << out.path;
        }
}

TEST(OutputSafety, BenchAndCodecBenchRefuseReportsOverTheirInputs)
{
    test::ScratchDir dir;
    const std::string arc = everestArchive(dir);
    const std::string tif = everestCopy(dir);
    const std::string arc_before = readFile(arc), tif_before = readFile(tif);
    for (const char* flag : {"--json-file", "--plot"}) {
        expectRefused(runCli({"bench", arc, "--frames", "2", "--size", "32x32", flag, arc}), arc,
                      arc);
        expectRefused(runCli({"codec-bench", tif, "--max-error", "4", "-q", flag, tif}), tif, tif);
    }
    EXPECT_TRUE(readFile(arc) == arc_before) << "the archive was changed";
    EXPECT_TRUE(readFile(tif) == tif_before) << "the raster was changed";
}

// --- Temporary files are created safely -----------------------------------------------------

// The old temporary name was OUTPUT.tmp.<pid>, opened with fopen("wb") (following
// symlinks): a symlink planted there for the pid redirected the whole output into the
// victim and left OUTPUT a symlink to it. The pid is known here before the CLI runs.
TEST_P(OutputSafetyTemporaries, SymlinksPlantedAtPredictableTemporaryNamesAreNeverWrittenThrough)
{
    test::ScratchDir dir, elsewhere;
    const std::string victim = elsewhere.path("victim");
    std::ofstream(victim) << "precious";
    const std::string arc = everestArchive(elsewhere);
    for (const auto& [command, input, name] :
         {std::tuple<std::string, std::string, std::string>{
              "build", test::dataPath("everest_crop.tif"), "out.ridge"},
          {"extract", arc, "out.tif"},
          {"hillshade", arc, "out.png"}}) {
        const std::string out = dir.path(name);
        std::vector<std::string> planted;
        SpawnOptions o;
        if (GetParam())
            o.env = kNamedTemporaries;
        o.before_exec = [&, &name = name](pid_t pid) {
            for (pid_t p = pid - 20; p <= pid + 20; ++p)
                for (const std::string& n :
                     {out + ".tmp." + std::to_string(p), out + ".tmp.check." + std::to_string(p),
                      out + ".tmp." + std::to_string(p) + ".aux.xml"}) {
                    fs::create_symlink(victim, n);
                    planted.push_back(n);
                }
            // The new names are random; plant the obvious guesses anyway.
            for (const std::string& guess :
                 {std::to_string(pid), std::string(16, '0'), std::string("0123456789abcdef")}) {
                const std::string n = dir.path("." + name + ".ridge-tmp-" + guess);
                fs::create_symlink(victim, n);
                planted.push_back(n);
            }
        };
        const CliResult r = runCli({command, input, "-o", out, "-q"}, o);
        EXPECT_EQ(r.exit_code, 0) << command << ": " << r.output;
        EXPECT_TRUE(readFile(victim) == "precious")
            << command << " wrote through a planted symlink";
        EXPECT_TRUE(fs::is_regular_file(fs::symlink_status(out))) << command;
        EXPECT_GT(fs::file_size(out), 0u) << command;
        for (const std::string& n : planted) {
            EXPECT_TRUE(fs::is_symlink(n)) << n;
            fs::remove(n);
        }
        EXPECT_EQ(othersIn(dir.dir(), {"out.ridge", "out.tif", "out.png"}),
                  std::vector<std::string>{});
    }
}

TEST(OutputSafety, AnOutputThatIsASymlinkToAnotherFileIsReplacedNotWrittenThrough)
{
    test::ScratchDir dir;
    const std::string victim = dir.path("victim");
    std::ofstream(victim) << "precious";
    const std::string out = dir.path("out.ridge");
    fs::create_symlink(victim, out);
    const CliResult r = runCli({"build", test::dataPath("everest_crop.tif"), "-o", out, "-q"});
    EXPECT_EQ(r.exit_code, 0) << r.output;
    EXPECT_EQ(readFile(victim), "precious");
    EXPECT_TRUE(fs::is_regular_file(fs::symlink_status(out)));
}

// --- Temporary files do not outlive their process ------------------------------------------

TEST_P(OutputSafetyTemporaries, KillNineMidBuildLeavesNoTemporaryOrTheNextBuildRemovesIt)
{
    test::ScratchDir out_dir;
    std::unique_ptr<Ridge> r = stoppedMidBuild(out_dir.dir(), GetParam());
    ::kill(r->pid(), SIGKILL);
    EXPECT_EQ(r->finish(), 128 + SIGKILL);
    if (!GetParam()) {
        EXPECT_EQ(othersIn(out_dir.dir(), {}), std::vector<std::string>{})
            << "an unnamed temporary dies with its process";
        return;
    }
    // The fallback's file has a name and survives SIGKILL; it is unlocked now, so the next
    // AtomicOutput for the same output removes it.
    EXPECT_EQ(othersIn(out_dir.dir(), {}).size(), 1u);
    SpawnOptions o;
    o.env = kNamedTemporaries;
    const CliResult next = runCli(
        {"build", test::dataPath("everest_crop.tif"), "-o", out_dir.path("out.ridge"), "-q"}, o);
    EXPECT_EQ(next.exit_code, 0) << next.output;
    EXPECT_EQ(othersIn(out_dir.dir(), {"out.ridge"}), std::vector<std::string>{});
}

// SIGINT, SIGTERM and SIGHUP cancel: the build unwinds, removes its temporary and then dies
// of the same signal (re-raised), so a shell reports 128 + N (130, 143, 129) and stops a loop
// the build was part of. The message says what happened.
TEST_P(OutputSafetyTemporaries, SigintSigtermAndSighupCancelABuildWithNoOutputAndNoTemporary)
{
    for (const int sig : {SIGTERM, SIGHUP, SIGINT}) {
        test::ScratchDir out_dir;
        std::unique_ptr<Ridge> r = stoppedMidBuild(out_dir.dir(), GetParam());
        ::kill(r->pid(), sig);
        ::kill(r->pid(), SIGCONT);
        EXPECT_EQ(r->finish(), 128 + sig) << r->output();
        EXPECT_TRUE(r->signalled());
        EXPECT_NE(r->output().find("interrupted by SIG"), std::string::npos) << r->output();
        EXPECT_EQ(othersIn(out_dir.dir(), {}), std::vector<std::string>{}) << "signal " << sig;
    }
}

TEST(OutputSafety, ABuildStartedWithSighupIgnoredLikeUnderNohupKeepsRunning)
{
    test::ScratchDir out_dir;
    SpawnOptions o;
    o.ignore_sighup = true;
    const std::string out = out_dir.path("out.ridge");
    Ridge r({"build", bigRaster(), "-o", out}, o);
    ASSERT_TRUE(r.waitFor("10")) << r.output();
    ::kill(r.pid(), SIGHUP);
    EXPECT_EQ(r.finish(), 0) << r.output();
    EXPECT_TRUE(fs::is_regular_file(out));
}

TEST(OutputSafety, ASecondSigtermTerminatesAtOnceAndStillLeavesNoTemporary)
{
    test::ScratchDir out_dir;
    std::unique_ptr<Ridge> r = stoppedMidBuild(out_dir.dir(), false);
    ::kill(r->pid(), SIGTERM);
    ::kill(r->pid(), SIGCONT);
    std::this_thread::sleep_for(std::chrono::milliseconds(1)); // the handler has run by now
    ::kill(r->pid(), SIGTERM);
    EXPECT_EQ(r->finish(), 128 + SIGTERM);
    EXPECT_EQ(othersIn(out_dir.dir(), {}), std::vector<std::string>{});
}

// RLIMIT_FSIZE: SIGXFSZ used to kill the build (leaving the temporary behind); now the write
// fails with EFBIG and the ordinary error path reports it and cleans up.
TEST_P(OutputSafetyTemporaries, AFileSizeLimitFailsCleanlyWithAMessageAndNoTemporary)
{
    test::ScratchDir dir;
    const std::string arc = everestArchive(dir);
    for (const auto& [command, input, name, phrase] :
         {std::tuple<std::string, std::string, std::string, std::string>{
              "build", test::dataPath("everest_crop.tif"), "out.ridge", "File too large"},
          {"extract", arc, "out.tif", "cannot write"}}) {
        test::ScratchDir out_dir;
        const std::string out = out_dir.path(name);
        SpawnOptions o;
        if (GetParam())
            o.env = kNamedTemporaries;
        o.file_size_limit = 16 * 1024;
        const CliResult r = runCli({command, input, "-o", out, "-q"}, o);
        EXPECT_EQ(r.exit_code, 1) << command << ": " << r.output;
        EXPECT_NE(r.output.find(out + ":"), std::string::npos) << r.output;
        EXPECT_NE(r.output.find(phrase), std::string::npos) << r.output;
        EXPECT_EQ(othersIn(out_dir.dir(), {}), std::vector<std::string>{}) << command;
    }
}

INSTANTIATE_TEST_SUITE_P(Modes, OutputSafetyTemporaries, ::testing::Values(false, true), modeName);

// --- Unwritable outputs -----------------------------------------------------------------------

TEST(OutputSafety, MissingOrReadOnlyOutputDirectoriesAreClearErrorsWithNothingLeft)
{
    test::ScratchDir dir;
    const std::string arc = everestArchive(dir);
    const std::string missing = dir.path("no/such/dir/out");
    for (const std::vector<std::string>& args :
         {std::vector<std::string>{"build", test::dataPath("everest_crop.tif"), "-o", missing},
          {"extract", arc, "-o", missing},
          {"hillshade", arc, "-o", missing}}) {
        const CliResult r = runCli(args);
        EXPECT_EQ(r.exit_code, 1) << r.output;
        EXPECT_NE(r.output.find(missing + ": cannot write"), std::string::npos) << r.output;
        EXPECT_NE(r.output.find("No such file or directory"), std::string::npos) << r.output;
        EXPECT_EQ(r.output.find("...10"), std::string::npos) << "checked before the work";
    }

    // Root writes anywhere: drop the capabilities that let it, so that the mode bits count.
    SpawnOptions o;
    if (::geteuid() == 0) {
        if (test::runShell("command -v setpriv").exit_code != 0)
            GTEST_SKIP() << "running as root without setpriv: cannot test a read-only directory";
        o.prefix = {"setpriv", "--bounding-set=-dac_override,-dac_read_search", "--"};
    }
    const fs::path ro = dir.dir() / "read-only";
    fs::create_directory(ro);
    fs::permissions(ro, fs::perms(0555));
    const std::string out = (ro / "out.ridge").string();
    const CliResult r = runCli({"build", test::dataPath("everest_crop.tif"), "-o", out, "-q"}, o);
    fs::permissions(ro, fs::perms(0755));
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_NE(r.output.find(out + ": cannot write"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("Permission denied"), std::string::npos) << r.output;
    EXPECT_TRUE(fs::is_empty(ro));
}

// --- Outputs are regular files; writes are checked ------------------------------------------

// extract and render replaced a FIFO or a character device with a regular file (as root,
// `-o /dev/null` replaced /dev/null). Every output is refused there before the work, naming
// it, and the special file is left as it was. (A device made here, never /dev/null itself:
// the older CLI this test may run against would replace it.)
TEST(OutputSafety, OutputsOntoAFifoADeviceOrASocketAreRefusedAndLeaveThemAsTheyWere)
{
    test::ScratchDir dir;
    const std::string arc = everestArchive(dir);
    struct Special {
        std::string path;
        std::string kind;
        std::function<bool()> unchanged;
    };
    std::vector<Special> specials;
    const std::string fifo = dir.path("fifo");
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    specials.push_back({fifo, "it is a FIFO", [=] { return fs::is_fifo(fifo); }});
    const std::string device = dir.path("null-device");
    if (::mknod(device.c_str(), S_IFCHR | 0666, ::makedev(1, 3)) == 0)
        specials.push_back(
            {device, "it is a character device", [=] { return fs::is_character_file(device); }});
    const std::string link = dir.path("link-to-dev-null");
    fs::create_symlink("/dev/null", link);
    specials.push_back(
        {link, "it is a symlink to a character device", [=] { return fs::is_symlink(link); }});
    const std::string sock = dir.path("socket");
    const int s = ::socket(AF_UNIX, SOCK_STREAM, 0);
    sockaddr_un address{};
    address.sun_family = AF_UNIX;
    std::snprintf(address.sun_path, sizeof address.sun_path, "%s", sock.c_str());
    ASSERT_EQ(::bind(s, reinterpret_cast<const sockaddr*>(&address), sizeof address), 0);
    specials.push_back({sock, "it is a socket", [=] { return fs::is_socket(sock); }});
    std::vector<std::string> keep = {"a.ridge"};
    for (const Special& sp : specials)
        keep.push_back(fs::path(sp.path).filename().string());

    for (const Special& sp : specials)
        for (const std::vector<std::string>& command :
             {std::vector<std::string>{"extract", arc},
              {"hillshade", arc},
              {"render", arc, "--size", "32x32", "-q"},
              {"build", test::dataPath("everest_crop.tif")}}) {
            std::vector<std::string> args = command;
            args.insert(args.end(), {"-o", sp.path});
            const CliResult r = runCli(args);
            SCOPED_TRACE(command[0] + " -o " + sp.path);
            EXPECT_EQ(r.exit_code, 1) << r.output;
            EXPECT_NE(r.output.find(sp.path + ": cannot write: " + sp.kind), std::string::npos)
                << r.output;
            EXPECT_EQ(r.output.find("...10"), std::string::npos) << "checked before the work";
            EXPECT_TRUE(sp.unchanged()) << "replaced";
            EXPECT_EQ(othersIn(dir.dir(), keep), std::vector<std::string>{});
        }
    ::close(s);
}

// Commands said success with stdout on a full disk or /dev/full: buffered output fails only
// when flushed, after the command's work. Each now exits 1 and names standard output; the
// shell's redirection is the only way in, so these run through it.
TEST(OutputSafety, AFailedWriteToStandardOutputIsAFailureThatSaysSo)
{
    test::ScratchDir dir;
    const std::string arc = everestArchive(dir);
    const std::string q = "'" + arc + "'";
    for (const std::string& args :
         {"info " + q, "info " + q + " --json", "verify " + q + " --json", "verify " + q + " -q",
          "query " + q + " 10 10 --pixel", "query " + q + " 10 10 --pixel --json",
          "render " + q + " -o '" + dir.path("r.png") + "' --size 32x32 --json",
          "extract " + q + " -o '" + dir.path("e.tif") + "' --json -q",
          "build '" + test::dataPath("everest_crop.tif") + "' -o '" + dir.path("b.ridge") +
              "' --json",
          std::string("info --help")}) {
        SCOPED_TRACE(args);
        // The group's stderr is captured; ridge's stdout goes to /dev/full.
        const test::CommandResult r =
            test::runShell("{ " + cliPath() + " " + args + " > /dev/full; }");
        EXPECT_EQ(r.exit_code, 1) << r.output;
        EXPECT_NE(r.output.find("standard output: cannot write: No space left on device"),
                  std::string::npos)
            << r.output;
        EXPECT_EQ(r.output.find("internal error"), std::string::npos) << r.output;
    }
    // Query from stdin too, whose answers are flushed line by line.
    const test::CommandResult r = test::runShell("{ printf '1 1\\n2 2\\n' | " + cliPath() +
                                                 " query " + q + " --pixel > /dev/full; }");
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_NE(r.output.find("standard output: cannot write"), std::string::npos) << r.output;
}
