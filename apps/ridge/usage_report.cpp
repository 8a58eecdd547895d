#include "usage_report.h"

#include "ridge/core/nearest_name.h"

#include <cctype>
#include <utility>

namespace ridge::cli {

namespace {

bool looksLikeANumber(const std::string& arg)
{
    // "-1", "-.5", "-1e3": values of flags such as --z-offset, not flags.
    return arg.size() > 1 && arg[0] == '-' &&
           (std::isdigit(static_cast<unsigned char>(arg[1])) || arg[1] == '.');
}

// Every visible spelling of `app`'s flags ("--frames", "-o"), hidden aliases excluded.
std::vector<std::string> flagNames(const CLI::App& app)
{
    std::vector<std::string> names;
    for (const CLI::Option* option : app.get_options()) {
        if (option->get_group().empty()) // hidden
            continue;
        for (const std::string& l : option->get_lnames())
            names.push_back("--" + l);
        for (const std::string& s : option->get_snames())
            names.push_back("-" + s);
    }
    return names;
}

std::string suggestion(const std::string& name, const std::vector<std::string>& candidates)
{
    const std::optional<std::string> nearest = nearestName(name, candidates);
    return nearest ? "; did you mean '" + *nearest + "'?" : "";
}

} // namespace

std::string describeUsageError(CLI::App& app, const std::vector<std::string>& args,
                               const CLI::ParseError& error)
{
    // The subcommand: the first argument that is not a flag (ridge's own flags take no value).
    size_t first = 0;
    while (first < args.size() && !args[first].empty() && args[first][0] == '-')
        ++first;
    std::vector<std::string> names;
    CLI::App* command = nullptr;
    for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) {
        names.push_back(sub->get_name());
        if (first < args.size() && sub->check_name(args[first]))
            command = sub;
    }
    if (!command) {
        if (first < args.size())
            return "unknown command '" + args[first] + "'" + suggestion(args[first], names) +
                   " (ridge --help lists the commands)";
        return std::string(error.what()) + " (ridge --help lists the commands)";
    }
    ++first;
    const std::string where = "ridge " + command->get_name();
    for (size_t i = first; i < args.size(); ++i) {
        const std::string& arg = args[i];
        if (arg == "--")
            break;
        if (arg.size() < 2 || arg[0] != '-' || looksLikeANumber(arg))
            continue;
        const std::string name = arg.substr(0, arg.find('='));
        if (command->get_option_no_throw(name) || app.get_option_no_throw(name))
            continue;
        // "-qv", "-b2": CLI11 reads a single dash and several letters as a cluster of
        // single-letter flags, or one with its value attached, when the first letter is one
        // of the command's; otherwise ("-projwin" where there is no -p) it is unknown.
        if (name[1] != '-' && name.size() > 2 && command->get_option_no_throw(name.substr(0, 2)))
            continue;
        return where + ": unknown option '" + name + "'" + suggestion(name, flagNames(*command)) +
               " (" + where + " --help lists its options)";
    }
    return where + ": " + error.what() + " (" + where + " --help lists its options)";
}

std::string withFlagNames(const std::string& message)
{
    // The library's parameter names (BuildOptions, HeadlessRenderOptions, ...) and the flags
    // that set them; one spelling per concept across the commands.
    static const std::pair<const char*, const char*> kFlags[] = {
        {"max_error", "--max-error"}, {"memory_limit_bytes", "--max-memory"},
        {"look_at", "--look-at"},     {"epsilon_px", "--error"},
        {"z_scale", "--z-scale"},     {"z_offset", "--z-offset"},
        {"patch_size", "--patch"},    {"block_cells", "--block"},
        {"fov_y_degrees", "--fov"},   {"measure_popping", "--popping"},
        {"data_type", "-ot"},         {"nodata", "-a_nodata"},
        {"creation_options", "-co"},  {"format", "-of"},
        {"projwin", "--projwin"},     {"srcwin", "--srcwin"},
    };
    auto isNameChar = [](char c) {
        return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
    };
    std::string hints;
    for (const auto& [parameter, flag] : kFlags) {
        const std::string p = parameter;
        for (size_t at = message.find(p); at != std::string::npos; at = message.find(p, at + 1)) {
            const bool starts = at == 0 || !isNameChar(message[at - 1]);
            const bool ends =
                at + p.size() == message.size() || !isNameChar(message[at + p.size()]);
            if (starts && ends) {
                hints += (hints.empty() ? "" : ", ") + p + " is " + flag;
                break;
            }
        }
    }
    return hints.empty() ? message : message + " (" + hints + ")";
}

} // namespace ridge::cli
