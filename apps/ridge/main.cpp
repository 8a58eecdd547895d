// ridge: command line for building, inspecting and checking .ridge terrain archives.
// Thin by design: parse arguments, call libridge, report, return an exit code:
//   0 success, 1 failure while running (files, archives, GDAL, a verify that finds problems,
//     a write that fails, standard output included),
//   2 usage (unknown command or flag, missing or malformed argument, value out of range);
//   an interrupt ends the process by its signal (SIGINT: the shell's 130).
#include "commands.h"
#include "range_check.h"
#include "terminal.h"
#include "usage_error.h"
#include "usage_report.h"

#include "ridge/core/error.h"

#include <CLI/CLI.hpp>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string_view>
#include <system_error>

namespace {

using namespace ridge::cli;

// Put before an argument that is a number spelt with '-' then a letter or a point ("-inf",
// "-.5"), which CLI11 would otherwise take for a cluster of short flags ("-i -n -f"); every
// option strips it again before anything reads the value (applyNumberRules). No flag starts
// with it.
constexpr char kNumberMark = '\x1f';

bool negativeNumberCliTakesForAFlag(std::string_view arg)
{
    return arg.size() > 1 && arg[0] == '-' && !(arg[1] >= '0' && arg[1] <= '9') &&
           detail::isDecimalNumber(arg);
}

void markNegativeNumbers(std::vector<std::string>& args)
{
    for (std::string& arg : args)
        if (negativeNumberCliTakesForAFlag(arg))
            arg.insert(arg.begin(), kNumberMark);
}

// Every option of `app` and its subcommands: the mark above removed, then numeric options
// (CLI11's FLOAT, INT and UINT) held to the one spelling rule of range_check.h, so that
// "0x10" is refused by every flag and positional, not read as 16 by some.
void applyNumberRules(CLI::App& app)
{
    for (CLI::Option* option : app.get_options()) {
        const std::string type = option->get_type_name();
        const bool real = type == "FLOAT", integer = type == "INT" || type == "UINT";
        const std::string name = option->get_name(false, true);
        option->transform(CLI::Validator(
            [real, integer, name](std::string& value) -> std::string {
                if (!value.empty() && value[0] == kNumberMark &&
                    negativeNumberCliTakesForAFlag(std::string_view(value).substr(1)))
                    value.erase(0, 1);
                if (real && !detail::isDecimalNumber(value))
                    throw UsageError(name + " " + value + ": must be a decimal number");
                if (integer && !detail::isDecimalInteger(value))
                    throw UsageError(name + " " + value + ": must be a decimal integer");
                return {};
            },
            ""));
    }
    for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; }))
        applyNumberRules(*sub);
}

// Whatever a command printed on stdout is checked before success is claimed: buffered
// output reaches a full disk or /dev/full only when flushed, and a failed write (ENOSPC,
// EIO, a closed descriptor) is a failure like any other, naming what could not be written.
int finishStandardOutput(int code)
{
    errno = 0;
    const bool failed = std::fflush(stdout) != 0 || std::ferror(stdout);
    if (!failed)
        return code;
    const int error = errno;
    std::fprintf(stderr, "\nridge: error: standard output: cannot write%s%s\n", error ? ": " : "",
                 error ? std::strerror(error) : "");
    return kExitFailure;
}

} // namespace

int main(int argc, char** argv)
{
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
    applyNumberRules(app);
    installInterruptHandler();
    std::vector<std::string> args(argv + (argc > 0 ? 1 : 0), argv + argc);
    for (std::string& arg : args)
        for (const char* gdal_style : Commands::kGdalStyleFlags)
            if (arg == gdal_style)
                arg = "-" + arg;
    markNegativeNumbers(args);
    try {
        try {
            std::vector<std::string> reversed(args.rbegin(), args.rend()); // CLI11's order
            app.parse(reversed);
        } catch (const CLI::CallForHelp& e) {
            return finishStandardOutput(app.exit(e));
        } catch (const CLI::CallForAllHelp& e) {
            return finishStandardOutput(app.exit(e));
        } catch (const CLI::CallForVersion& e) {
            return finishStandardOutput(app.exit(e));
        } catch (const CLI::ParseError& e) {
            std::string message = describeUsageError(app, args, e);
            std::erase(message, kNumberMark); // CLI11 quotes arguments as it was given them
            std::fprintf(stderr, "ridge: error: %s\n", message.c_str());
            return kExitUsage;
        }
        return finishStandardOutput(commands.run());
    } catch (const ridge::Cancelled&) {
        std::fprintf(stderr, "\nridge: interrupted by %s; no output was written\n",
                     interruptSignalName());
        return exitAfterInterrupt();
    } catch (const UsageError& e) {
        std::fprintf(stderr, "\nridge: error: %s\n", e.what());
        return kExitUsage;
    } catch (const ridge::Error& e) {
        std::fprintf(stderr, "\nridge: error: %s\n", withFlagNames(e.what()).c_str());
        finishStandardOutput(kExitFailure);
        return kExitFailure;
    } catch (const std::system_error& e) {
        // fmt::print throws this when stdout refuses a write (it checks fwrite's count).
        if (std::ferror(stdout)) {
            std::fprintf(stderr, "\nridge: error: standard output: cannot write: %s\n",
                         e.code().message().c_str());
            return kExitFailure;
        }
        std::fprintf(stderr, "\nridge: internal error: %s\n", e.what());
        return kExitFailure;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "\nridge: internal error: %s\n", e.what());
        return kExitFailure;
    }
}
