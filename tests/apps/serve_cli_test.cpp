// `ridge serve` as a user runs it: a process on a loopback port, spoken to over HTTP, stopped
// by SIGTERM and SIGINT with exit status 0; bad archives and options refused before serving.
#include "test_support.h"

#include <gtest/gtest.h>
#include <httplib.h>

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <thread>

extern char** environ;

namespace {

// `ridge serve ARGS --port 0` as a child process; its first stdout line is its URL.
class ServeProcess {
  public:
    explicit ServeProcess(const std::vector<std::string>& args)
    {
        int out[2];
        EXPECT_EQ(::pipe(out), 0);
        posix_spawn_file_actions_t actions;
        posix_spawn_file_actions_init(&actions);
        posix_spawn_file_actions_adddup2(&actions, out[1], STDOUT_FILENO);
        posix_spawn_file_actions_addclose(&actions, out[0]);
        std::vector<std::string> all = {RIDGE_CLI_PATH, "serve", "--port", "0"};
        all.insert(all.end(), args.begin(), args.end());
        std::vector<char*> argv;
        for (std::string& a : all)
            argv.push_back(a.data());
        argv.push_back(nullptr);
        EXPECT_EQ(posix_spawn(&pid_, RIDGE_CLI_PATH, &actions, nullptr, argv.data(), environ), 0);
        posix_spawn_file_actions_destroy(&actions);
        ::close(out[1]);
        // The URL line, within 30 s.
        std::string line;
        pollfd p{out[0], POLLIN, 0};
        while (line.find('\n') == std::string::npos && ::poll(&p, 1, 30000) > 0) {
            char buffer[256];
            const ssize_t n = ::read(out[0], buffer, sizeof buffer);
            if (n <= 0)
                break;
            line.append(buffer, size_t(n));
        }
        ::close(out[0]);
        const size_t colon = line.rfind(':');
        if (line.rfind("http://127.0.0.1:", 0) == 0 && colon != std::string::npos)
            port_ = std::atoi(line.c_str() + colon + 1);
    }
    ~ServeProcess()
    {
        if (pid_ > 0 && !reaped_) {
            ::kill(pid_, SIGKILL);
            ::waitpid(pid_, nullptr, 0);
        }
    }
    int port() const { return port_; }
    // Sends `signal` and waits up to 10 s; the exit status, or -1 when it did not exit.
    int stopWith(int signal)
    {
        ::kill(pid_, signal);
        for (int i = 0; i < 1000; ++i) {
            int status = 0;
            if (::waitpid(pid_, &status, WNOHANG) == pid_) {
                reaped_ = true;
                return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
        return -1;
    }

  private:
    pid_t pid_ = -1;
    int port_ = 0;
    bool reaped_ = false;
};

} // namespace

TEST(ServeCli, ServesUntilSigtermOrSigintAndExitsCleanly)
{
    const ridge::test::ScratchDir dir;
    const std::string archive =
        ridge::test::buildEverestWithCli(dir, "everest.ridge", "--patch 33");
    for (const int signal : {SIGTERM, SIGINT}) {
        ServeProcess serve({archive});
        ASSERT_GT(serve.port(), 0);
        httplib::Client c("127.0.0.1", serve.port());
        c.set_read_timeout(30);
        const auto list = c.Get("/tilesets.json");
        ASSERT_TRUE(list);
        EXPECT_EQ(list->status, 200);
        EXPECT_NE(list->body.find("\"everest\""), std::string::npos) << list->body;
        const auto tile = c.Get("/everest/0/1/0.terrain");
        ASSERT_TRUE(tile);
        EXPECT_EQ(tile->status, 200);
        EXPECT_EQ(serve.stopWith(signal), 0);
    }
}

TEST(ServeCli, RefusesBadArchivesAndOptions)
{
    const ridge::test::ScratchDir dir;
    const std::string junk = dir.path("junk.ridge");
    {
        std::ofstream(junk) << "not an archive";
    }
    const auto missing = ridge::test::runRidge("serve --port 0 " + dir.path("none.ridge"));
    EXPECT_NE(missing.exit_code, 0);
    EXPECT_NE(missing.output.find("none.ridge"), std::string::npos) << missing.output;
    const auto bad = ridge::test::runRidge("serve --port 0 " + junk);
    EXPECT_NE(bad.exit_code, 0);
    EXPECT_NE(bad.output.find("junk.ridge"), std::string::npos) << bad.output;
    for (const std::string options : {"--port 70000", "--port -1", "--threads 0", "--cells 0",
                                      "--samplers 0", "--cache-mb nan", "--watermask sea"}) {
        const auto r = ridge::test::runRidge("serve " + options + " " + junk);
        EXPECT_EQ(r.exit_code, 2) << options << ": " << r.output;
    }
}
