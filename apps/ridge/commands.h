#pragma once
// The subcommands of `ridge` and their options.
#include "ridge/pipeline/build.h"
#include "ridge/pipeline/extract.h"
#include "ridge/pipeline/hillshade.h"

#include <CLI/CLI.hpp>
#include <optional>
#include <string>
#include <vector>

namespace ridge::cli {

// `ridge codec-bench` (codec_bench_command.cpp): ridge's codec against the anchor codecs.
class CodecBenchCommand {
public:
    void registerWith(CLI::App& app);
    bool parsed() const { return command_ && command_->parsed(); }
    int run();

private:
    CLI::App* command_ = nullptr;
    std::string input_;
    std::vector<double> max_errors_{0.5, 1.0, 4.0, 16.0};
    int tile_size_ = 256;
    std::string ridge_codec_ = "progressive";
    std::string json_path_;
    std::string plot_path_;
    bool quiet_ = false;
};

class Commands {
public:
    void registerAll(CLI::App& app);
    // Runs the subcommand that was parsed; returns the process exit code.
    int run();

private:
    void validateBuildOptions() const;
    int runBuild();
    int runInfo();
    int runVerify();
    int runExtract();
    int runHillshade();

    CLI::App* build_ = nullptr;
    CLI::App* info_ = nullptr;
    CLI::App* verify_ = nullptr;
    CLI::App* extract_ = nullptr;
    CLI::App* hillshade_ = nullptr;

    bool quiet_ = false;
    bool json_ = false;
    std::string input_;
    std::string output_;
    std::string archive_;
    // build
    BuildOptions build_options_;
    // verify
    std::string source_;
    // extract / hillshade
    int level_ = -1;
    std::vector<int> window_;
    HillshadeOptions hillshade_options_;
    CodecBenchCommand codec_bench_;
};

} // namespace ridge::cli
