#include "terminal.h"

#include <atomic>
#include <csignal>
#include <cstdio>
#include <memory>

namespace ridge::cli {

namespace {

std::atomic<bool> g_interrupted{false};

extern "C" void onSignal(int)
{
    g_interrupted.store(true);
}

} // namespace

void installInterruptHandler()
{
    std::signal(SIGINT, onSignal);
    std::signal(SIGTERM, onSignal);
}

bool interrupted()
{
    return g_interrupted.load();
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
