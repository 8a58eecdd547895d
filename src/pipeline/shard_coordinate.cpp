// The coordinator of a sharded build (pipeline/shard.h): levels 0..k, the codec's training,
// the top levels' encoding and the shards' parents.
#include "shard_internal.h"

#include "ridge/core/error.h"
#include "ridge/core/file_identity.h"
#include "ridge/core/json_text.h"
#include "ridge/pyramid/patch_context.h"

#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <map>
#include <memory>

namespace ridge {

using namespace shard_internal;
using namespace build_stages;

namespace {

// One file per shard, each of the plan, its kind and key: by shard id.
std::vector<std::unique_ptr<archive::ShardFileReader>>
openPerShard(const ShardPlan& plan, const std::vector<std::string>& paths,
             archive::ShardFileKind kind, const std::function<uint64_t(const PlanShard&)>& key)
{
    std::vector<std::unique_ptr<archive::ShardFileReader>> files(plan.shards.size());
    for (const std::string& path : paths) {
        auto file = std::make_unique<archive::ShardFileReader>(path);
        const int64_t id = file->header().shard;
        if (id < 0 || id >= int64_t(plan.shards.size()))
            throw Error(path + ": names shard " + std::to_string(id) +
                        ", which the plan does not have");
        file->expect(kind, plan.layout_hash, id);
        if (files[size_t(id)])
            throw Error(path + ": a second " + shardFileKindName(kind) + " file of shard " +
                        std::to_string(id) + " (the first: " + files[size_t(id)]->path() + ")");
        if (file->header().key != key(plan.shards[size_t(id)]))
            throw Error(path + ": the " + shardFileKindName(kind) + " of shard " +
                        std::to_string(id) +
                        " was made from other inputs (stale, or from another step): make it again");
        files[size_t(id)] = std::move(file);
    }
    for (size_t id = 0; id < files.size(); ++id)
        if (!files[id])
            throw Error("shard " + std::to_string(id) + ": no " + shardFileKindName(kind) +
                        " file given (" + std::to_string(paths.size()) + " given, the plan has " +
                        std::to_string(files.size()) + " shards)");
    return files;
}

uint16_t infoCode(const nlohmann::json& info, const char* key, const std::string& path)
{
    const auto it = info.find(key);
    if (it == info.end() || !it->is_number_unsigned() || it->get<uint64_t>() > 65535)
        throw Error(path + ": INFO." + key + " is missing or not a code (0..65535)");
    return it->get<uint16_t>();
}

int64_t infoCount(const nlohmann::json& info, const char* key, const std::string& path)
{
    const auto it = info.find(key);
    if (it == info.end() || !it->is_number_unsigned() || it->get<uint64_t>() > (uint64_t{1} << 52))
        throw Error(path + ": INFO." + key + " is missing or not a count");
    return it->get<int64_t>();
}

double infoMetres(const nlohmann::json& info, const char* key, const std::string& path)
{
    const auto it = info.find(key);
    if (it == info.end() || !it->is_number() ||
        !(std::abs(it->get<double>()) <= kMaxAbsHeightMetres))
        throw Error(path + ": INFO." + key + " is missing or not a height");
    return it->get<double>();
}

} // namespace

ShardStepReport coordinate(const ShardPlan& plan, const std::vector<std::string>& summary_paths,
                           const std::string& previous_top,
                           const std::vector<std::string>& observation_paths,
                           const std::string& output)
{
    const auto start = std::chrono::steady_clock::now();
    std::vector<std::string> inputs = {plan.path, plan.source, previous_top};
    inputs.insert(inputs.end(), summary_paths.begin(), summary_paths.end());
    inputs.insert(inputs.end(), observation_paths.begin(), observation_paths.end());
    refuseOutputOverInput(output, inputs);

    BuildContext ctx = planContext(plan);
    const PyramidGeometry& g = ctx.geometry;
    const int n = g.patchSize(), c = g.cells(), k = plan.shard_level;
    const auto summaries = openPerShard(plan, summary_paths, archive::ShardFileKind::Summary,
                                        [](const PlanShard& s) { return summaryKey(s); });

    // 1. Level k from the shards' roots, with their bounds and ranges; their owned statistics.
    CodeGrid level_k;
    level_k.width = g.levelWidth(k);
    level_k.height = g.levelHeight(k);
    level_k.codes.assign(size_t(level_k.width) * level_k.height, 0);
    const bool water = summaries[0]->has(kTagRootFlags);
    SampleFlagsGrid flags_k =
        water ? SampleFlagsGrid(level_k.width, level_k.height) : SampleFlagsGrid();
    const PyramidGeometry gk(level_k.width, level_k.height, n);
    if (gk.levelCount() != k + 1)
        throw Error("internal error: levels 0.." + std::to_string(k) + " geometry");
    PatchErrors errors = makePatchErrors(gk);
    io::IngestStats stats;
    double min_metres = INFINITY, max_metres = -INFINITY;
    for (const PlanShard& s : plan.shards) {
        const archive::ShardFileReader& file = *summaries[size_t(s.id)];
        const nlohmann::json info = readInfo(file);
        const std::vector<uint8_t> root = file.read(kTagRoot, uint64_t(n) * n * 2);
        if (root.size() != size_t(n) * n * 2)
            throw Error(file.path() + ": ROOT section is not " + std::to_string(n) + "² codes");
        if (file.has(kTagRootFlags) != water)
            throw Error(file.path() + ": shard " + std::to_string(s.id) +
                        (water ? " has no water flags, shard 0 has"
                               : " has water flags, shard 0 has none"));
        std::vector<uint8_t> root_flags;
        if (water)
            root_flags = file.read(kTagRootFlags, uint64_t(n) * n);
        if (water && root_flags.size() != size_t(n) * n)
            throw Error(file.path() + ": RFLG section is not " + std::to_string(n) + "² flags");
        const auto* codes = reinterpret_cast<const uint16_t*>(root.data());
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const int x = s.root.x * c + i, y = s.root.y * c + j;
                if (x >= level_k.width || y >= level_k.height)
                    continue;
                level_k.at(x, y) = codes[size_t(j) * n + i];
                if (water)
                    flags_k.set(x, y, root_flags[size_t(j) * n + i] & kSampleFlagBits);
            }
        const int64_t index = gk.patchIndex(s.root);
        errors.min_code[size_t(index)] = infoCode(info, "root_min_code", file.path());
        errors.max_code[size_t(index)] = infoCode(info, "root_max_code", file.path());
        const auto err = info.find("root_err_appr");
        if (err == info.end() || !err->is_number() || !(err->get<double>() >= 0) ||
            !(err->get<double>() <= 65535))
            throw Error(file.path() + ": INFO.root_err_appr is missing or not a bound");
        errors.err_appr[size_t(index)] = err->get<float>();
        stats.valid_samples += infoCount(info, "owned_samples", file.path());
        stats.water_samples += infoCount(info, "owned_water", file.path());
        min_metres = std::min(min_metres, infoMetres(info, "min_metres", file.path()));
        max_metres = std::max(max_metres, infoMetres(info, "max_metres", file.path()));
    }
    if (stats.valid_samples != int64_t(plan.width) * plan.height)
        throw Error("the shards' summaries own " + std::to_string(stats.valid_samples) +
                    " samples, the raster has " +
                    std::to_string(int64_t(plan.width) * plan.height));

    // 2. Levels 0..k−1 from level k: Err_Int, ranges, Err_Appr up to the root.
    const LevelPyramid pyramid(level_k, gk, PyramidFilter::Decimate);
    if (k > 0)
        measurePatches(pyramid, 0, k - 1, errors);
    accumulatePatchErrors(gk, k, errors);
    if (water)
        ctx.flags = std::make_unique<SampleFlagsPyramid>(std::move(flags_k), k, g);

    // 3. Training: this process observes levels 0..k, the shards the rest.
    int stage = 0;
    if (!previous_top.empty()) {
        const archive::ShardFileReader top(previous_top);
        top.expect(archive::ShardFileKind::Top, plan.layout_hash, -1);
        const nlohmann::json info = readInfo(top);
        stage = int(info.value("pending_stage", 0));
        if (stage <= 0)
            throw Error(previous_top + ": a final top file: there is no stage left to train");
        restoreCodec(ctx, top);
    }
    if (std::unique_ptr<CodecTrainer> trainer = ctx.codec->trainer()) {
        parallelFor(gk.patchCount(), 4, [&](int64_t index) {
            const PatchId p = gk.patchAt(index);
            observePatch(ctx, *trainer, pyramid.level(p.level),
                         p.level > 0 ? &pyramid.level(p.level - 1) : nullptr, p, p);
        });
        if (stage == 0) {
            for (const auto& file : summaries) {
                const std::vector<uint8_t> seen =
                    file->read(kTagObservations, kMaxObservationBytes);
                trainer->mergeObservations(seen.data(), seen.size());
            }
        } else {
            const archive::ShardFileReader top(previous_top);
            const uint64_t state = hashBytes(top.read(kTagCodec, kMaxObservationBytes));
            const auto observed =
                openPerShard(plan, observation_paths, archive::ShardFileKind::Observations,
                             [&](const PlanShard& s) { return observationKey(s, state); });
            for (const auto& file : observed) {
                const std::vector<uint8_t> seen =
                    file->read(kTagObservations, kMaxObservationBytes);
                trainer->mergeObservations(seen.data(), seen.size());
            }
        }
        ctx.codec = trainer->finish();
        if (ctx.codec->trainer()) { // another stage: the shards observe again
            archive::ShardFileWriter out(
                output, {archive::ShardFileKind::Top, plan.layout_hash, -1, plan.hash});
            const std::string info = jsonText(nlohmann::json{{"pending_stage", stage + 1}});
            out.addSection(kTagInfo, info.data(), info.size());
            out.addSection(kTagCodec, ctx.codec->trainingState());
            out.finish();
            ShardStepReport r;
            r.pending_stage = stage + 1;
            r.output_bytes = out.bytesWritten();
            r.seconds =
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            return r;
        }
    } else if (!observation_paths.empty()) {
        throw Error("observations given, but the codec has nothing left to learn");
    }

    // 4. Levels 0..k−1 encoded top down; level k−1's reconstructions are the shards' parents.
    archive::ShardFileWriter out(output,
                                 {archive::ShardFileKind::Top, plan.layout_hash, -1, plan.hash});
    BlobSink blobs(out);
    const LevelSpan levels{[&](int l) { return g.patchCount(l); },
                           [&](int l, int64_t j) { return g.patchAt(g.firstPatchIndex(l) + j); },
                           [&](PatchId p) { return g.patchIndex(p) - g.firstPatchIndex(p.level); }};
    std::vector<std::vector<uint16_t>> parents;
    encodeTopDown(
        ctx, 0, k, levels,
        [&](PatchId p, const uint16_t* parent) {
            const size_t index = size_t(g.patchIndex(p));
            const PatchSummary summary{errors.min_code[index], errors.max_code[index],
                                       errors.err_appr[index]};
            return encodePatch(ctx, pyramid.level(p.level), p, p, summary, parent);
        },
        [&](EncodedPatch& e) { blobs.add(e); }, parents, true);
    blobs.finish();
    if (k > 0 && ctx.codec->needsParent(k)) { // level k−1's, kept by encodeTopDown
        std::vector<uint16_t> all;
        for (const std::vector<uint16_t>& p : parents)
            all.insert(all.end(), p.begin(), p.end());
        out.addSection(kTagParents, all.data(), all.size() * sizeof(uint16_t));
    }

    // 5. What the archive's header, tables and metadata need.
    const io::CodeRowReader source(plan.source, plan.options.ingest);
    const io::IngestStats base = source.stats();
    stats.data_type = base.data_type;
    stats.nodata = base.nodata;
    stats.exact = base.exact;
    stats.z_scale = base.z_scale;
    stats.z_offset = base.z_offset;
    stats.fill_voids = plan.options.ingest.fill_voids;
    stats.min_metres = min_metres;
    stats.max_metres = max_metres;
    const std::string metadata =
        metadataJson(plan.source_name, stats, source.geo(), ctx, plan.options);
    const std::string info = jsonText(nlohmann::json{{"pending_stage", 0}, {"metadata", metadata}});
    out.addSection(kTagInfo, info.data(), info.size());
    out.addSection(kTagCodec, ctx.codec->trainingState());
    out.addSection(kTagTables, ctx.codec->storeTables());
    out.finish();
    ShardStepReport r;
    r.output_bytes = out.bytesWritten();
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return r;
}

} // namespace ridge
