#include "terminal.h"

#include <atomic>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <signal.h>
#include <unistd.h>

namespace ridge::cli {

namespace {

std::atomic<int> g_signal{0};
static_assert(std::atomic<int>::is_always_lock_free, "written from a signal handler");

constexpr int kInterruptSignals[] = {SIGINT, SIGTERM, SIGHUP};

extern "C" void onSignal(int signal_number)
{
    int none = 0;
    g_signal.compare_exchange_strong(none, signal_number);
}

} // namespace

void installInterruptHandler()
{
    struct sigaction action {};
    action.sa_handler = onSignal;
    sigemptyset(&action.sa_mask);
    // SA_RESTART: reads and writes in progress are not failed with EINTR (the cancel comes at
    // the next progress report); SA_RESETHAND: the next signal of the kind kills at once.
    action.sa_flags = SA_RESTART | SA_RESETHAND;
    for (const int s : kInterruptSignals) {
        // A signal ignored at startup stays ignored: `nohup ridge build ...` must survive
        // the terminal closing, and a shell's background jobs ignore SIGINT on purpose.
        struct sigaction previous {};
        if (sigaction(s, nullptr, &previous) == 0 && previous.sa_handler == SIG_IGN)
            continue;
        sigaction(s, &action, nullptr);
    }
    struct sigaction ignore {};
    ignore.sa_handler = SIG_IGN;
    sigemptyset(&ignore.sa_mask);
    sigaction(SIGXFSZ, &ignore, nullptr);
}

bool interrupted()
{
    return g_signal.load() != 0;
}

const char* interruptSignalName()
{
    switch (g_signal.load()) {
    case SIGINT:
        return "SIGINT";
    case SIGTERM:
        return "SIGTERM";
    case SIGHUP:
        return "SIGHUP";
    default:
        return "an interrupt";
    }
}

int exitAfterInterrupt()
{
    const int s = g_signal.load();
    if (s == 0)
        return 130;
    std::fflush(nullptr);
    struct sigaction action {};
    action.sa_handler = SIG_DFL;
    sigemptyset(&action.sa_mask);
    sigaction(s, &action, nullptr);
    sigset_t set;
    sigemptyset(&set);
    sigaddset(&set, s);
    pthread_sigmask(SIG_UNBLOCK, &set, nullptr);
    ::raise(s);
    std::exit(128 + s);
}

Progress terminalProgress(bool quiet)
{
    // Ticks every 2.5%: numbers at multiples of 10, dots in between.
    auto printed = std::make_shared<int>(-1);
    return [quiet, printed](double fraction) {
        if (!quiet) {
            const int tick = static_cast<int>(fraction * 40.0 + 1e-9);
            while (*printed < tick && *printed < 40) {
                ++*printed;
                if (*printed % 4 == 0)
                    std::fprintf(stderr, "%d", *printed / 4 * 10);
                else
                    std::fputc('.', stderr);
                if (*printed == 40)
                    std::fputs(" - done.\n", stderr);
            }
            std::fflush(stderr);
        }
        return !interrupted();
    };
}

} // namespace ridge::cli
