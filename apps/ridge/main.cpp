// ridge: command line for building, inspecting and checking .ridge terrain archives.
// Thin by design: parse arguments, call libridge, report, return an exit code:
//   0 success, 1 failure while running (files, archives, GDAL, a verify that finds problems),
//   2 usage (unknown command or flag, missing or malformed argument, value out of range);
//   an interrupt ends the process by its signal (SIGINT: the shell's 130).
#include "commands.h"
#include "terminal.h"
#include "usage_error.h"
#include "usage_report.h"

#include "ridge/core/error.h"

#include <CLI/CLI.hpp>
#include <cstdio>

int main(int argc, char** argv)
{
    using namespace ridge::cli;
    CLI::App app{"ridge: real-time terrain from compressed multiresolution elevation data"};
    app.name("ridge");
    app.require_subcommand(1);
    app.set_version_flag("--version", "ridge 0.1.0");
    Commands commands;
    commands.registerAll(app);
    // Each --help names only what its command takes: the --json sentence only where --json is.
    const std::string exit_status = "Exit status: 0 success, 1 failure, 2 usage error.";
    app.footer(exit_status);
    for (CLI::App* command : app.get_subcommands([](CLI::App*) { return true; }))
        command->footer(command->get_option_no_throw("--json")
                            ? exit_status + " --json prints one JSON document on stdout (human "
                                            "text then goes to stderr or is not printed)."
                            : exit_status);
    installInterruptHandler();
    std::vector<std::string> args(argv + (argc > 0 ? 1 : 0), argv + argc);
    for (std::string& arg : args)
        for (const char* gdal_style : Commands::kGdalStyleFlags)
            if (arg == gdal_style)
                arg = "-" + arg;
    try {
        try {
            std::vector<std::string> reversed(args.rbegin(), args.rend()); // CLI11's order
            app.parse(reversed);
        } catch (const CLI::CallForHelp& e) {
            return app.exit(e);
        } catch (const CLI::CallForAllHelp& e) {
            return app.exit(e);
        } catch (const CLI::CallForVersion& e) {
            return app.exit(e);
        } catch (const CLI::ParseError& e) {
            std::fprintf(stderr, "ridge: error: %s\n", describeUsageError(app, args, e).c_str());
            return kExitUsage;
        }
        return commands.run();
    } catch (const ridge::Cancelled&) {
        std::fprintf(stderr, "\nridge: interrupted by %s; no output was written\n",
                     interruptSignalName());
        return exitAfterInterrupt();
    } catch (const UsageError& e) {
        std::fprintf(stderr, "\nridge: error: %s\n", e.what());
        return kExitUsage;
    } catch (const ridge::Error& e) {
        std::fprintf(stderr, "\nridge: error: %s\n", withFlagNames(e.what()).c_str());
        return kExitFailure;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "\nridge: internal error: %s\n", e.what());
        return kExitFailure;
    }
}
