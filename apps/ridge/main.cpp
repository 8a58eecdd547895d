// ridge: command line for building, inspecting and checking .ridge terrain archives.
// Thin by design: parse arguments, call libridge, report, return an exit code.
#include "commands.h"
#include "terminal.h"

#include "ridge/core/error.h"

#include <CLI/CLI.hpp>
#include <cstdio>

int main(int argc, char** argv)
{
    CLI::App app{"ridge: real-time terrain from compressed multiresolution elevation data"};
    app.require_subcommand(1);
    app.set_version_flag("--version", "ridge 0.1.0");
    ridge::cli::Commands commands;
    commands.registerAll(app);
    ridge::cli::installInterruptHandler();
    try {
        app.parse(argc, argv);
        return commands.run();
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    } catch (const ridge::Cancelled&) {
        std::fprintf(stderr, "\nridge: interrupted by %s; no output was written\n",
                     ridge::cli::interruptSignalName());
        return ridge::cli::exitAfterInterrupt();
    } catch (const ridge::Error& e) {
        std::fprintf(stderr, "\nridge: error: %s\n", e.what());
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "\nridge: internal error: %s\n", e.what());
        return 2;
    }
}
