// `ridge codec-bench INPUT`: parse, run the bench (ridge_codecbench), print the tables,
// write the optional JSON and plot.
#include "commands.h"
#include "range_check.h"
#include "terminal.h"
#include "usage_error.h"

#include "ridge/codec/codec_registry.h"
#include "ridge/codecbench/codec_bench.h"
#include "ridge/core/atomic_output.h"
#include "ridge/core/file_identity.h"
#include "ridge/io/dataset_files.h"

#include <fmt/core.h>

namespace ridge::cli {

void CodecBenchCommand::registerWith(CLI::App& app)
{
    command_ = app.add_subcommand(
        "codec-bench",
        "Compare ridge's codec with error-bounded anchor codecs (LERC, JPEG-LS, JPEG 2000, "
        "JPEG XL at efforts 7 and 9 and 9 progressive, MED+zstd, ZFP) on one raster; for ridge "
        "also the bytes a cold cache fetches for a near, mid and far view at 1920x1080, "
        "ε = 2 px");
    command_->add_option("input", input_, "Input raster (anything GDAL reads)")->required();
    command_
        ->add_option("--max-error", max_errors_,
                     "L-inf bounds in metres; repeat or give several (default 0.5 1 4 16)")
        ->expected(1, 64)
        ->check(inRange("--max-error", codecbench::CodecBenchOptions::kMaxErrorRange));
    command_->add_option("--tile", tile_size_, "Anchors' tile side in samples, 0 = whole grid")
        ->capture_default_str()
        ->check(inIntegerRange("--tile", 0, codecbench::CodecBenchOptions::kMaxTileSize));
    command_
        ->add_option("--ridge-codec", ridge_codecs_,
                     "ridge's codecs, one row each, as build --codec takes them; repeat for "
                     "several, or `all` for every lossy codec registered and the variants it "
                     "asks to be compared (a lossy codec is built at each bound, a lossless one "
                     "once per bound; a mode without a bound, fractal,mode=paper, codes the "
                     "anchors' tiles and its errors are measured)")
        ->expected(1, 16)
        ->capture_default_str();
    command_->add_flag("--overviews", overviews_,
                       "Also code each single-level anchor's overviews (the finest level "
                       "decimated by 2, 4, ... down to 256 samples a side, as gdaladdo builds "
                       "them): one more row per such anchor, for what a single-level format "
                       "pays for levels of detail");
    command_->add_flag("--json", json_,
                       "Print every number as JSON on stdout (the tables then go to stderr)");
    command_->add_option("--json-file", json_path_, "Write every number as JSON to a file");
    command_->add_option("--plot", plot_path_, "Write ratio vs bound as a PNG");
    command_->add_flag("-q,--quiet", quiet_, "No progress output");
}

int CodecBenchCommand::run()
{
    std::vector<std::string> ridge_codecs;
    for (const std::string& codec : ridge_codecs_) {
        if (codec == "all") {
            for (const CodecInfo& c : codecRegistry())
                if (c.lossy) {
                    ridge_codecs.push_back(c.name);
                    ridge_codecs.insert(ridge_codecs.end(), c.bench_variants.begin(),
                                        c.bench_variants.end());
                }
            continue;
        }
        if (const std::string problem = codecSpecProblem(codec); !problem.empty())
            throw UsageError("--ridge-codec " + codec + ": " + problem);
        ridge_codecs.push_back(codec);
    }
    for (const std::string& out : {json_path_, plot_path_})
        if (!out.empty()) { // before the run, not after it
            refuseOutputOverInput(out, io::datasetFiles(input_));
            checkOutputWritable(out);
        }
    codecbench::CodecBenchOptions options;
    options.max_errors = max_errors_;
    options.tile_size = tile_size_;
    options.overviews = overviews_;
    options.ridge_codecs = ridge_codecs;
    options.progress = terminalProgress(quiet_);
    const codecbench::CodecBenchReport report = codecbench::runCodecBench(input_, options);
    fmt::print(json_ ? stderr : stdout, "{}", codecbench::formatCodecBenchTable(report));
    if (json_)
        fmt::print("{}", codecbench::formatCodecBenchJson(report));
    if (!json_path_.empty())
        codecbench::writeCodecBenchJson(report, json_path_);
    if (!plot_path_.empty())
        codecbench::writeCodecBenchPlot(report, plot_path_);
    int violated = 0;
    for (const codecbench::BoundResult& b : report.bounds)
        for (const codecbench::CodecRow& row : b.rows)
            violated += row.scope == "pyramid" && !row.bound_ok ? 1 : 0;
    // ridge's own bound is a promise: missing it is a failure. Anchors that miss theirs are
    // results, reported in the table.
    if (violated) {
        fmt::print(stderr,
                   "ridge: error: ridge's codecs missed their bound {} times over {} bounds\n",
                   violated, report.bounds.size());
        return 1;
    }
    return 0;
}

} // namespace ridge::cli
