// The shard's own steps (pipeline/shard.h): summary, observations, segment.
#include "shard_internal.h"

#include "ridge/core/error.h"
#include "ridge/core/file_identity.h"
#include "ridge/core/json_text.h"
#include "ridge/core/sample_flag_bits.h"
#include "ridge/pyramid/patch_context.h"

#include <nlohmann/json.hpp>

#include <bit>
#include <chrono>
#include <filesystem>

namespace ridge {

using namespace shard_internal;
using namespace build_stages;

static_assert(std::endian::native == std::endian::little,
              "shard files store codes and records little-endian, as the host does");

namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start)
{
    return std::chrono::duration<double>(Clock::now() - start).count();
}

// Shows `trainer` every patch of the subtree below its root (the root's level is the
// coordinator's to observe: it holds the root's parent).
void observeSubtree(const BuildContext& ctx, const Subtree& tree, CodecTrainer& trainer)
{
    const int k = tree.shard().root.level;
    for (int l = k + 1; l < ctx.geometry.levelCount(); ++l)
        parallelFor(tree.layout().count(l), 4, [&](int64_t j) {
            const PatchId p = tree.layout().patchAt(l, j);
            observePatch(ctx, trainer, tree.view(l), &tree.view(l - 1), tree.layout().local(p), p);
        });
}

// Publishes `out` and reports the step.
ShardStepReport finished(archive::ShardFileWriter& out, const Subtree& tree,
                         Clock::time_point start)
{
    out.finish();
    ShardStepReport r;
    r.samples = tree.samples_read;
    r.output_bytes = out.bytesWritten();
    r.seconds = secondsSince(start);
    return r;
}

archive::ShardFileHeader headerFor(const ShardPlan& plan, archive::ShardFileKind kind,
                                   int64_t shard, uint64_t key)
{
    return {kind, plan.layout_hash, shard, key};
}

// The top file a shard reads: a final or pending one of this plan.
std::unique_ptr<archive::ShardFileReader> openTop(const ShardPlan& plan, const std::string& top)
{
    auto reader = std::make_unique<archive::ShardFileReader>(top);
    reader->expect(archive::ShardFileKind::Top, plan.layout_hash, -1);
    return reader;
}

ShardStepReport skipped(const std::string& output)
{
    ShardStepReport r;
    r.skipped = true;
    std::error_code ignored;
    r.output_bytes = std::filesystem::file_size(output, ignored);
    return r;
}

} // namespace

ShardStepReport buildShardSummary(const ShardPlan& plan, int64_t id, const std::string& output,
                                  bool skip_unchanged)
{
    const auto start = Clock::now();
    const PlanShard& shard = plan.shard(id);
    const archive::ShardFileHeader header =
        headerFor(plan, archive::ShardFileKind::Summary, id, summaryKey(shard));
    if (skip_unchanged && archive::shardFileMatches(output, header))
        return skipped(output);
    refuseOutputOverInput(output, {plan.path, plan.source});
    BuildContext ctx = planContext(plan);
    const Subtree tree(plan, id);
    const int n = ctx.geometry.patchSize();
    const PatchId root = shard.root;

    std::vector<uint16_t> root_codes(size_t(n) * n);
    extractPatch(tree.view(root.level), n, tree.layout().local(root), root_codes.data());
    const PatchSummary s = tree.summary(root);
    const nlohmann::json info = {
        {"owned_samples", tree.owned_samples}, {"owned_water", tree.owned_water},
        {"min_metres", tree.min_metres},       {"max_metres", tree.max_metres},
        {"root_min_code", s.min_code},         {"root_max_code", s.max_code},
        {"root_err_appr", s.err_appr}};
    archive::ShardFileWriter out(output, header);
    out.addSection(kTagInfo, jsonText(info).data(), jsonText(info).size());
    out.addSection(kTagRoot, root_codes.data(), root_codes.size() * sizeof(uint16_t));
    if (tree.hasFlags()) {
        const PatchSampleFlags flags = tree.flags(root);
        std::vector<uint8_t> raw(size_t(n) * n, 0);
        if (flags.kind == PatchSampleFlags::Kind::AllWater)
            std::fill(raw.begin(), raw.end(), uint8_t(kSampleWater));
        else if (flags.kind == PatchSampleFlags::Kind::Mixed)
            raw = flags.flags;
        out.addSection(kTagRootFlags, raw);
    }
    if (std::unique_ptr<CodecTrainer> trainer = ctx.codec->trainer()) {
        observeSubtree(ctx, tree, *trainer);
        out.addSection(kTagObservations, trainer->saveObservations());
    }
    return finished(out, tree, start);
}

ShardStepReport observeShard(const ShardPlan& plan, int64_t id, const std::string& top,
                             const std::string& output, bool skip_unchanged)
{
    const auto start = Clock::now();
    const PlanShard& shard = plan.shard(id);
    const std::unique_ptr<archive::ShardFileReader> top_file_ptr = openTop(plan, top);
    const archive::ShardFileReader& top_file = *top_file_ptr;
    const uint64_t state = hashBytes(top_file.read(kTagCodec, kMaxObservationBytes));
    const archive::ShardFileHeader header =
        headerFor(plan, archive::ShardFileKind::Observations, id, observationKey(shard, state));
    if (skip_unchanged && archive::shardFileMatches(output, header))
        return skipped(output);
    refuseOutputOverInput(output, {plan.path, plan.source, top});
    BuildContext ctx = planContext(plan);
    restoreCodec(ctx, top_file);
    std::unique_ptr<CodecTrainer> trainer = ctx.codec->trainer();
    if (!trainer)
        throw Error(top + ": its codec is trained: there is nothing to observe; encode the "
                          "shards with it (ridge build --plan --shard --top)");
    const Subtree tree(plan, id);
    observeSubtree(ctx, tree, *trainer);
    archive::ShardFileWriter out(output, header);
    out.addSection(kTagObservations, trainer->saveObservations());
    return finished(out, tree, start);
}

ShardStepReport buildShardSegment(const ShardPlan& plan, int64_t id, const std::string& top,
                                  const std::string& output, bool skip_unchanged)
{
    const auto start = Clock::now();
    const PlanShard& shard = plan.shard(id);
    const std::unique_ptr<archive::ShardFileReader> top_file_ptr = openTop(plan, top);
    const archive::ShardFileReader& top_file = *top_file_ptr;
    if (readInfo(top_file).value("pending_stage", 0) != 0)
        throw Error(top + ": the codec is not trained yet (the coordinator asks the shards to "
                          "observe first): not the final top file");
    BuildContext ctx = planContext(plan);
    restoreCodec(ctx, top_file);
    const int n = ctx.geometry.patchSize();
    const int k = shard.root.level;
    std::vector<uint16_t> parent;
    if (ctx.codec->needsParent(k)) {
        // Level k−1's reconstructions, one per patch in index order.
        const PatchId up = shard.root.parent();
        const uint64_t patch_bytes = uint64_t(n) * n * sizeof(uint16_t);
        const int64_t position = int64_t(up.y) * ctx.geometry.patchesX(k - 1) + up.x;
        if (top_file.sectionSize(kTagParents) !=
            patch_bytes * uint64_t(ctx.geometry.patchCount(k - 1)))
            throw Error(top + ": PRNT section size does not match level " + std::to_string(k - 1));
        parent.resize(size_t(n) * n);
        top_file.readAt(kTagParents, uint64_t(position) * patch_bytes, parent.data(), patch_bytes);
    }
    const uint64_t state = hashBytes(top_file.read(kTagCodec, kMaxObservationBytes));
    const archive::ShardFileHeader header =
        headerFor(plan, archive::ShardFileKind::Segment, id,
                  segmentKey(shard, state, parent.empty() ? nullptr : parent.data(), n));
    if (skip_unchanged && archive::shardFileMatches(output, header))
        return skipped(output);
    refuseOutputOverInput(output, {plan.path, plan.source, top});
    const Subtree tree(plan, id);

    // Top down, level by level, each patch from its parent's reconstruction (writeLevels'
    // order within the subtree); blobs appended, records kept for the end.
    archive::ShardFileWriter out(output, header);
    BlobSink blobs(out);
    const SubtreeLayout& layout = tree.layout();
    const LevelSpan span{[&](int l) { return layout.count(l); },
                         [&](int l, int64_t j) { return layout.patchAt(l, j); },
                         [&](PatchId p) { // the root's parent: the one reconstruction given
                             return p.level < k
                                        ? 0
                                        : layout.position(p) - layout.firstPosition(p.level);
                         }};
    std::vector<std::vector<uint16_t>> above;
    if (!parent.empty())
        above.push_back(std::move(parent));
    encodeTopDown(
        ctx, k, ctx.geometry.levelCount(), span,
        [&](PatchId p, const uint16_t* parent_codes) {
            PatchSampleFlags flags{PatchSampleFlags::Kind::None, n, {}};
            if (tree.hasFlags())
                flags = tree.flags(p);
            return encodePatch(ctx, tree.view(p.level), layout.local(p), p, tree.summary(p),
                               parent_codes, &flags);
        },
        [&](EncodedPatch& e) { blobs.add(e); }, above);
    blobs.finish();
    return finished(out, tree, start);
}

} // namespace ridge
