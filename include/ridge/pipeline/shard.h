#pragma once
// Builds past one machine (docs/DESIGN.md, "Sharded builds"): a raster planned into the
// subtrees below one quadtree level (shards), each built by its own process, wherever a
// distributed engine runs it (python/ridge_dask: Dask distributed), then merged into one
// archive byte-identical to `ridge build` of the same raster with the same options.
//
//   plan      makePlan: the level-k patches the raster covers, each with its finest window
//             (decimation needs no halo beyond the shared edge) and the inputs under it;
//             options, geometry and a hash of the inputs' contents.
//   summary   buildShardSummary: a shard's pyramid and bounds bottom up (Err_Int, Err_Appr,
//             ranges), its root's level-k samples and flags, and what it shows the codec's
//             trainer (stage 0).
//   top       coordinate: levels 0..k from the shards' roots, Err_Appr up to level 0, the
//             codec trained on every patch of the archive (the coordinator's levels and every
//             shard's observations: training is exact integer sums, so the codec is the same
//             for any split); a codec that learns in stages asks the shards to observe again
//             (observeShard) with what it has learned so far. When trained: levels 0..k−1
//             encoded, and each shard's parent reconstruction.
//   segment   buildShardSegment: the shard's subtree encoded top down from that parent.
//   merge     mergeShards: the top's and the segments' blobs copied in the order `ridge build`
//             writes them, every CRC checked, one index; atomic, memory bounded by the index.
//
// Every step validates what it reads (plan fields and hashes, the kind, plan and shard of
// each file, the inputs' sizes and times against the plan) and names the shard it refuses.
#include "ridge/core/progress.h"
#include "ridge/io/raster_mosaic.h"
#include "ridge/pipeline/build.h"
#include "ridge/pyramid/pyramid_geometry.h"

#include <cstdint>
#include <string>
#include <vector>

namespace ridge {

struct PlanInput {
    std::string path;          // absolute
    uint64_t bytes = 0;        // size and modification time when planned: a step refuses an
    int64_t mtime_ns = 0;      // input that has changed since
    uint64_t content = 0;      // FNV-1a 64 of the file's bytes (what the shard hashes cover)
    io::PixelWindow footprint; // its pixels in the source
};

struct PlanShard {
    int64_t id = 0;          // row-major position among the level-k patches
    PatchId root;            // the level-k patch
    io::PixelWindow window;  // the finest samples the subtree covers, shared edges included
    std::vector<int> inputs; // indices into ShardPlan::inputs under the window
    uint64_t hash = 0;       // layout hash + the contents of its inputs
};

struct ShardPlan {
    std::string path;        // the plan file
    std::string source;      // absolute path of the raster the shards read (a mosaic VRT)
    std::string source_name; // the source as `ridge build` would record it
    std::string data_type;
    int width = 0;
    int height = 0;
    BuildOptions options; // memory_limit_bytes and progress are not stored
    int shard_level = 0;
    int level_count = 0;
    std::vector<PlanInput> inputs;
    std::vector<PlanShard> shards;
    uint64_t layout_hash = 0; // options, source size and type, geometry, shard windows
    uint64_t hash = 0;        // layout + every shard's hash

    PyramidGeometry geometry() const;
    // Throws Error("PLAN: no shard ID (0..N−1)").
    const PlanShard& shard(int64_t id) const;
};

// Plans a sharded build of `inputs` (one raster, or several joined into a mosaic VRT written
// beside the plan as PLAN_STEM.vrt) with `options` below level `shard_level`, and writes the
// plan (JSON, docs/FORMAT.md "Shard plan") atomically at `plan_path`. Refuses what a shard
// cannot build exactly as `ridge build` would: the Neville filter (its support crosses shard
// edges), a water layer, a vertical shift; voids are refused by the shard that meets them.
// A source that is not 8/16-bit integers is surveyed here (as `ridge build` does) and its
// code mapping stored in the plan (options.ingest.code_mapping), which every shard reads by.
ShardPlan makePlan(const std::vector<std::string>& inputs, const BuildOptions& options,
                   int shard_level, const std::string& plan_path);

// Reads and validates a plan: every field's type and range, shards exactly the level-k
// patches once each with their windows, the hashes. Throws Error naming the plan and field.
ShardPlan loadPlan(const std::string& plan_path);

struct ShardStepReport {
    bool skipped = false; // the output existed, made from the same inputs
    int64_t samples = 0;  // finest samples the step read
    uint64_t output_bytes = 0;
    double seconds = 0;
    int pending_stage = 0; // coordinate: the training stage the shards must observe; 0 done
};

// `skip_unchanged`: when `output` is already the file these inputs make (same kind, plan,
// shard and key), leave it and report skipped.
ShardStepReport buildShardSummary(const ShardPlan& plan, int64_t shard, const std::string& output,
                                  bool skip_unchanged = false);
ShardStepReport observeShard(const ShardPlan& plan, int64_t shard, const std::string& top,
                             const std::string& output, bool skip_unchanged = false);
// `summaries`: one per shard, any order; `previous_top` and `observations` (one per shard)
// when the previous top file asked for a training stage.
ShardStepReport coordinate(const ShardPlan& plan, const std::vector<std::string>& summaries,
                           const std::string& previous_top,
                           const std::vector<std::string>& observations, const std::string& output);
ShardStepReport buildShardSegment(const ShardPlan& plan, int64_t shard, const std::string& top,
                                  const std::string& output, bool skip_unchanged = false);

struct MergeReport {
    uint64_t bytes = 0;
    int64_t patches = 0;
    double seconds = 0;
};
// `files`: the final top file and one segment per shard, any order.
MergeReport mergeShards(const ShardPlan& plan, const std::vector<std::string>& files,
                        const std::string& output, const Progress& progress = {});

} // namespace ridge
