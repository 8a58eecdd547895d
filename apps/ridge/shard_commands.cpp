// Sharded builds on the command line (pipeline/shard.h): `ridge plan`, the steps of
// `ridge build --plan` a distributed driver runs (python/ridge_dask), and `ridge merge`.
#include "command_text.h"
#include "commands.h"
#include "range_check.h"
#include "terminal.h"
#include "usage_error.h"

#include "ridge/core/json_text.h"
#include "ridge/core/line_reader.h"
#include "ridge/pipeline/shard.h"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <sys/resource.h>

namespace ridge::cli {

namespace {

uint64_t peakRssBytes()
{
    struct rusage usage {};
    ::getrusage(RUSAGE_SELF, &usage);
    return uint64_t(usage.ru_maxrss) * 1024;
}

} // namespace

void Commands::registerShardSteps(CLI::App* build)
{
    const char* group = "Sharded build steps (ridge plan; scripts/ridge-dask runs them)";
    build->add_option("--plan", plan_path_, "The plan (ridge plan) whose step this is")
        ->group(group)
        ->type_name("PLAN");
    build->add_option("--shard", shard_, "The shard this step builds (an id of the plan)")
        ->group(group)
        ->check(inIntegerRange("--shard", 0, INT32_MAX));
    build
        ->add_flag("--summary", shard_summary_,
                   "The shard's pyramid, bounds and root for the coordinator")
        ->group(group);
    build
        ->add_option("--observe", observe_top_,
                     "What the shard shows the codec's trainer, at the stage of this top file")
        ->group(group)
        ->type_name("TOP");
    build
        ->add_flag("--coordinate", coordinate_,
                   "The coordinator: levels 0..k, training, the top levels (needs --summaries)")
        ->group(group);
    build
        ->add_option("--top", top_,
                     "With --shard: encode the shard from this final top file; with "
                     "--coordinate: the previous top file, whose stage --observations answer")
        ->group(group)
        ->type_name("TOP");
    build->add_option("--summaries", summaries_, "Every shard's summary (--coordinate)")
        ->group(group)
        ->type_name("FILE...");
    build->add_option("--observations", observations_, "Every shard's observations (--coordinate)")
        ->group(group)
        ->type_name("FILE...");
    build
        ->add_flag("--skip-unchanged", skip_unchanged_,
                   "Keep the output when it exists and was made from the same inputs")
        ->group(group);
}

void Commands::registerPlanAndMerge(CLI::App& app)
{
    plan_ = app.add_subcommand(
        "plan", "Plan a sharded build: the subtrees below --shard-level, their windows and "
                "inputs, for ridge build --plan and ridge merge (scripts/ridge-dask runs it all)");
    plan_->add_option("input", inputs_,
                      "Input rasters: one, or tiles joined into a mosaic VRT beside the plan "
                      "(as gdalbuildvrt)");
    plan_
        ->add_option("--input-file-list", input_file_list_,
                     "A text file naming one input per line (as gdalbuildvrt -input_file_list)")
        ->type_name("FILE");
    plan_
        ->add_option("--shard-level", shard_level_,
                     "The quadtree level whose patches are the shards (0: one shard)")
        ->required()
        ->check(inIntegerRange("--shard-level", 0, 31));
    plan_->add_option("-o,--output", output_, "The plan file (.json)")->required();
    addBuildOptions(plan_);
    plan_->add_flag("--json", json_, "Print the plan's shards as JSON on stdout");
    addCommonFlags(plan_, quiet_);

    merge_ = app.add_subcommand("merge",
                                "Merge a sharded build's top file and segments into one archive");
    merge_->add_option("plan", plan_path_, "The plan")->required();
    merge_->add_option("files", inputs_, "The final top file and every shard's segment")
        ->required();
    merge_->add_option("-o,--output", output_, "Output archive (.ridge)")->required();
    merge_->add_flag("--json", json_, "Print the merge's figures as JSON on stdout");
    addCommonFlags(merge_, quiet_);
}

int Commands::runPlan()
{
    std::vector<std::string> inputs = inputs_;
    if (!input_file_list_.empty()) {
        LineReader lines(input_file_list_, 4096, uint64_t{1} << 30);
        while (const std::optional<LineReader::Line> line = lines.next()) {
            if (line->too_long)
                throw UsageError(fmt::format("--input-file-list {}: line {} is longer than 4096 "
                                             "bytes",
                                             input_file_list_, line->number));
            if (!line->text.empty())
                inputs.push_back(line->text);
        }
    }
    if (inputs.empty())
        throw UsageError("plan: no input (give rasters or --input-file-list FILE)");
    input_ = inputs.front();
    settleBuildOptions();
    const ShardPlan plan = makePlan(inputs, build_options_, shard_level_, output_);
    if (json_) {
        nlohmann::json shards = nlohmann::json::array();
        for (const PlanShard& s : plan.shards)
            shards.push_back(
                {{"id", s.id},
                 {"hash", fmt::format("{:016x}", s.hash)},
                 {"window", {s.window.x, s.window.y, s.window.width, s.window.height}}});
        fmt::print("{}\n", jsonText(nlohmann::json{{"plan", output_},
                                                   {"source", plan.source},
                                                   {"hash", fmt::format("{:016x}", plan.hash)},
                                                   {"layout_hash",
                                                    fmt::format("{:016x}", plan.layout_hash)},
                                                   {"shard_level", plan.shard_level},
                                                   {"level_count", plan.level_count},
                                                   {"shards", shards}},
                                    -1));
    } else if (!quiet_) {
        fmt::print("{}: {} shards at level {} of {} ({}x{} samples from {}), {} inputs\n", output_,
                   plan.shards.size(), plan.shard_level, plan.level_count, plan.width, plan.height,
                   plan.source, plan.inputs.size());
    }
    return 0;
}

int Commands::runShardStep()
{
    if (!input_.empty())
        throw UsageError("build --plan: no INPUT (the plan names the source)");
    const int steps = int(shard_summary_) + int(!observe_top_.empty()) + int(coordinate_) +
                      int(!coordinate_ && !shard_summary_ && observe_top_.empty() && !top_.empty());
    if (steps != 1)
        throw UsageError("build --plan: name one step: --shard ID --summary, --shard ID --observe "
                         "TOP, --coordinate --summaries FILE..., or --shard ID --top TOP");
    if (coordinate_ == (shard_ >= 0))
        throw UsageError(coordinate_ ? "build --plan --coordinate: no --shard (it reads them all)"
                                     : "build --plan: --shard ID is required for this step");
    if (!coordinate_ && (!summaries_.empty() || !observations_.empty()))
        throw UsageError("build --plan: --summaries and --observations are --coordinate's");
    const ShardPlan plan = loadPlan(plan_path_);
    const char* step = "encode";
    ShardStepReport r;
    if (shard_summary_) {
        step = "summary";
        r = buildShardSummary(plan, shard_, output_, skip_unchanged_);
    } else if (!observe_top_.empty()) {
        step = "observe";
        r = observeShard(plan, shard_, observe_top_, output_, skip_unchanged_);
    } else if (coordinate_) {
        step = "coordinate";
        if (summaries_.empty())
            throw UsageError("build --plan --coordinate: --summaries FILE... is required");
        r = coordinate(plan, summaries_, top_, observations_, output_);
    } else {
        r = buildShardSegment(plan, shard_, top_, output_, skip_unchanged_);
    }
    nlohmann::json j = {{"step", step},
                        {"skipped", r.skipped},
                        {"seconds", r.seconds},
                        {"output", output_},
                        {"output_bytes", r.output_bytes},
                        {"samples", r.samples},
                        {"peak_rss_bytes", peakRssBytes()}};
    if (coordinate_)
        j["pending_stage"] = r.pending_stage;
    else
        j["shard"] = shard_;
    if (json_)
        fmt::print("{}\n", jsonText(j, -1));
    else if (!quiet_)
        fmt::print("{} {}: {}{} ({}, {:.2f} s)\n", step,
                   coordinate_ ? std::string("coordinator") : fmt::format("shard {}", shard_),
                   output_, r.skipped ? " unchanged, kept" : "", humanBytes(r.output_bytes),
                   r.seconds);
    return 0;
}

int Commands::runMerge()
{
    const ShardPlan plan = loadPlan(plan_path_);
    const MergeReport r = mergeShards(plan, inputs_, output_, terminalProgress(quiet_ || json_));
    if (json_)
        fmt::print("{}\n", jsonText(nlohmann::json{{"step", "merge"},
                                                   {"output", output_},
                                                   {"bytes", r.bytes},
                                                   {"patches", r.patches},
                                                   {"seconds", r.seconds},
                                                   {"peak_rss_bytes", peakRssBytes()}},
                                    -1));
    else if (!quiet_)
        fmt::print("{}: {} patches, {} ({:.2f} s)\n", output_, r.patches, humanBytes(r.bytes),
                   r.seconds);
    return 0;
}

} // namespace ridge::cli
