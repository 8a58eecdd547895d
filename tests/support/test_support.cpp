#include "test_support.h"

#include <algorithm>
#include <array>
#include <cstdio>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>
#include <sys/wait.h>

namespace ridge::test {

std::string dataPath(const std::string& name)
{
    return std::string(RIDGE_TEST_DATA_DIR) + "/" + name;
}

ScratchDir::ScratchDir()
{
    std::random_device rd;
    dir_ = std::filesystem::temp_directory_path() /
           ("ridge-test-" + std::to_string(rd()) + std::to_string(rd()));
    std::filesystem::create_directories(dir_);
}

ScratchDir::~ScratchDir()
{
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
}

std::string readFile(const std::string& path)
{
    std::ifstream in(path, std::ios::binary);
    std::stringstream content;
    content << in.rdbuf();
    return content.str();
}

std::vector<std::string> namesIn(const std::filesystem::path& dir)
{
    std::vector<std::string> names;
    for (const auto& entry : std::filesystem::directory_iterator(dir))
        names.push_back(entry.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

std::vector<std::string> temporariesIn(const std::filesystem::path& dir)
{
    std::vector<std::string> names;
    for (const auto& entry : std::filesystem::directory_iterator(dir)) {
        const std::string name = entry.path().filename().string();
        if (name.find(".ridge-tmp-") != std::string::npos ||
            name.find(".tmp.") != std::string::npos)
            names.push_back(name);
    }
    return names;
}

namespace {

CommandResult runCapturing(const std::string& command_line)
{
    CommandResult result;
    FILE* pipe = ::popen(command_line.c_str(), "r");
    if (!pipe)
        return result;
    std::array<char, 4096> buf;
    size_t n;
    while ((n = std::fread(buf.data(), 1, buf.size(), pipe)) > 0)
        result.output.append(buf.data(), n);
    const int status = ::pclose(pipe);
    result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    return result;
}

} // namespace

CommandResult runShell(const std::string& command)
{
    return runCapturing(command + " 2>&1");
}

#ifdef RIDGE_CLI_PATH
CommandResult runRidge(const std::string& args)
{
    return runShell(std::string(RIDGE_CLI_PATH) + " " + args);
}

CommandResult runRidgeStdout(const std::string& args)
{
    return runCapturing(std::string(RIDGE_CLI_PATH) + " " + args + " 2>/dev/null");
}

std::string buildEverestWithCli(const ScratchDir& dir, const std::string& name,
                                const std::string& args)
{
    return buildWithCli(dir, "everest_crop.tif", name, args);
}

std::string buildWithCli(const ScratchDir& dir, const std::string& data_file,
                         const std::string& name, const std::string& args)
{
    const std::string arc = dir.path(name);
    const CommandResult r =
        runRidge("build '" + dataPath(data_file) + "' -o '" + arc + "' -q " + args);
    if (r.exit_code != 0)
        throw std::runtime_error("ridge build " + data_file + " " + args + " failed: " + r.output);
    return arc;
}
#endif

} // namespace ridge::test
