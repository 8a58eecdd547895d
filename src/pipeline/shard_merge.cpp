// `ridge merge`: one archive from a sharded build's top file and segments (pipeline/shard.h).
#include "shard_internal.h"

#include "ridge/archive/archive_writer.h"
#include "ridge/core/crc32.h"
#include "ridge/core/error.h"
#include "ridge/core/file_identity.h"
#include "ridge/pipeline/build_memory.h"

#include <nlohmann/json.hpp>

#include <chrono>
#include <map>
#include <memory>
#include <optional>

namespace ridge {

using namespace shard_internal;

namespace {

// A file's records, checked against the patches it must hold: each exactly once, its blob
// inside the BLOB section.
struct Part {
    std::string path;
    std::vector<archive::PatchRecord> records; // by the patch's position in the part
    std::optional<SubtreeLayout> layout;       // a segment's
};

// The blob of `rec` from `file`, its CRC-32 checked.
void readBlob(const archive::ShardFileReader& file, const archive::PatchRecord& rec,
              std::vector<uint8_t>& blob)
{
    blob.resize(rec.size);
    file.readAt(kTagBlobs, rec.offset, blob.data(), blob.size());
    if (crc32(blob.data(), blob.size()) != rec.crc32)
        throw Error(file.path() + ": patch " + std::to_string(rec.level) + "/" +
                    std::to_string(rec.x) + "/" + std::to_string(rec.y) +
                    ": CRC-32 mismatch (the segment is damaged)");
}

// Reads and checks the RECS of `file`, which must hold exactly the patches `expected(rec)`
// places at 0..count−1.
std::vector<archive::PatchRecord>
readRecords(const archive::ShardFileReader& file, int64_t count,
            const std::function<int64_t(const archive::PatchRecord&)>& position)
{
    const uint64_t bytes = uint64_t(count) * archive::kIndexEntrySize;
    const std::vector<uint8_t> raw = file.read(kTagRecords, bytes);
    if (raw.size() != bytes)
        throw Error(file.path() + ": " + std::to_string(raw.size() / archive::kIndexEntrySize) +
                    " patches, the plan gives it " + std::to_string(count));
    const uint64_t blob_bytes = file.sectionSize(kTagBlobs);
    std::vector<archive::PatchRecord> records(static_cast<size_t>(count));
    std::vector<bool> seen(size_t(count), false);
    for (int64_t i = 0; i < count; ++i) {
        const archive::PatchRecord r =
            archive::parseRecord(raw.data() + i * archive::kIndexEntrySize);
        const std::string name =
            std::to_string(r.level) + "/" + std::to_string(r.x) + "/" + std::to_string(r.y);
        const int64_t at = position(r);
        if (at < 0 || at >= count)
            throw Error(file.path() + ": patch " + name + " is not one of its patches");
        if (seen[size_t(at)])
            throw Error(file.path() + ": patch " + name + " twice");
        if (r.offset > blob_bytes || r.size > blob_bytes - r.offset || r.block_errors_size > r.size)
            throw Error(file.path() + ": patch " + name + ": its blob lies outside the data");
        seen[size_t(at)] = true;
        records[size_t(at)] = r;
    }
    return records;
}

} // namespace

MergeReport mergeShards(const ShardPlan& plan, const std::vector<std::string>& files,
                        const std::string& output, const Progress& progress)
{
    const auto start = std::chrono::steady_clock::now();
    std::vector<std::string> inputs = files;
    inputs.push_back(plan.path);
    inputs.push_back(plan.source);
    refuseOutputOverInput(output, inputs);
    checkOutputWritable(output);
    build_stages::BuildContext ctx = planContext(plan);
    const PyramidGeometry& g = ctx.geometry;
    const int k = plan.shard_level, n = g.patchSize();

    // 1. The top file among `files`, then each shard's segment, checked against it.
    std::string top_path;
    for (const std::string& path : files) {
        const archive::ShardFileReader file(path);
        if (file.header().kind == archive::ShardFileKind::Top) {
            if (!top_path.empty())
                throw Error(path + ": a second top file (the first: " + top_path + ")");
            top_path = path;
        }
    }
    if (top_path.empty())
        throw Error("no top file among the " + std::to_string(files.size()) +
                    " given: `ridge build --plan --coordinate` writes it");
    const archive::ShardFileReader top(top_path);
    top.expect(archive::ShardFileKind::Top, plan.layout_hash, -1);
    const nlohmann::json info = readInfo(top);
    if (info.value("pending_stage", -1) != 0 || !info.contains("metadata") ||
        !info["metadata"].is_string())
        throw Error(top_path + ": not a final top file (the codec is still training)");
    const std::vector<uint8_t> state = top.read(kTagCodec, kMaxObservationBytes);
    const uint64_t state_hash = hashBytes(state);
    const bool parents = top.has(kTagParents);
    const uint64_t patch_bytes = uint64_t(n) * n * sizeof(uint16_t);
    if (parents && top.sectionSize(kTagParents) != patch_bytes * uint64_t(g.patchCount(k - 1)))
        throw Error(top_path + ": PRNT section size does not match level " + std::to_string(k - 1));

    const int64_t top_count = k > 0 ? g.firstPatchIndex(k) : 0;
    Part top_part{top_path,
                  readRecords(top, top_count,
                              [&](const archive::PatchRecord& r) {
                                  const PatchId p{int(r.level), int(r.x), int(r.y)};
                                  return p.level < k && g.exists(p) ? g.patchIndex(p) : -1;
                              }),
                  std::nullopt};
    std::vector<Part> segments(plan.shards.size());
    std::vector<bool> given(plan.shards.size(), false);
    std::vector<uint16_t> parent(size_t(n) * n);
    for (const std::string& path : files) {
        if (path == top_path)
            continue;
        const archive::ShardFileReader file(path);
        const int64_t id = file.header().shard;
        if (file.header().kind != archive::ShardFileKind::Segment || id < 0 ||
            id >= int64_t(plan.shards.size()))
            throw Error(path + ": is a " + shardFileKindName(file.header().kind) + " file" +
                        (id >= 0 ? " of shard " + std::to_string(id) : std::string()) +
                        ", not a segment of this plan's shards");
        file.expect(archive::ShardFileKind::Segment, plan.layout_hash, id);
        if (given[size_t(id)])
            throw Error(path + ": a second segment of shard " + std::to_string(id) +
                        " (the first: " + segments[size_t(id)].path + ")");
        const PlanShard& shard = plan.shards[size_t(id)];
        if (parents) {
            const PatchId up = shard.root.parent();
            top.readAt(kTagParents,
                       uint64_t(int64_t(up.y) * g.patchesX(k - 1) + up.x) * patch_bytes,
                       parent.data(), patch_bytes);
        }
        if (file.header().key !=
            segmentKey(shard, state_hash, parents ? parent.data() : nullptr, n))
            throw Error(path + ": the segment of shard " + std::to_string(id) +
                        " was built from other inputs, codec tables or parent than this top "
                        "file's (stale): build it again");
        const SubtreeLayout layout(g, shard.root);
        segments[size_t(id)] = {
            path,
            readRecords(file, layout.total(),
                        [&](const archive::PatchRecord& r) {
                            return layout.position({int(r.level), int(r.x), int(r.y)});
                        }),
            layout};
        given[size_t(id)] = true;
    }
    for (size_t id = 0; id < given.size(); ++id)
        if (!given[id])
            throw Error("shard " + std::to_string(id) + ": no segment given (" +
                        std::to_string(files.size() - 1) + " given, the plan has " +
                        std::to_string(given.size()) + " shards)");

    // 2. Blobs in the order `ridge build` writes them: a streamed build the finest level first,
    // then 0..L−2; otherwise level by level. Each level row by row; a shard row's segments
    // are open while its rows are copied.
    std::vector<int> order;
    const bool streamed = buildStreams(plan.options) && g.finestLevel() > 0;
    if (streamed)
        order.push_back(g.finestLevel());
    for (int l = 0; l < g.levelCount(); ++l)
        if (!(streamed && l == g.finestLevel()))
            order.push_back(l);
    archive::ArchiveWriter writer(output, ctx.header);
    std::vector<uint8_t> blob;
    int64_t written = 0;
    for (int l : order) {
        if (l < k) {
            for (int64_t i = g.firstPatchIndex(l); i < g.firstPatchIndex(l) + g.patchCount(l);
                 ++i) {
                const archive::PatchRecord& rec = top_part.records[size_t(i)];
                readBlob(top, rec, blob);
                writer.copyPatch(rec, blob.data());
                ++written;
            }
            continue;
        }
        const int d = l - k;
        for (int row = 0; row < g.patchesY(k); ++row) {
            std::vector<std::unique_ptr<archive::ShardFileReader>> open(size_t(g.patchesX(k)));
            for (int x = 0; x < g.patchesX(k); ++x)
                open[size_t(x)] = std::make_unique<archive::ShardFileReader>(
                    segments[size_t(int64_t(row) * g.patchesX(k) + x)].path);
            const int y_end = std::min((row + 1) << d, g.patchesY(l));
            for (int y = row << d; y < y_end; ++y)
                for (int x = 0; x < g.patchesX(l); ++x) {
                    const int sx = x >> d;
                    const Part& part = segments[size_t(int64_t(row) * g.patchesX(k) + sx)];
                    const int64_t at = part.layout->position({l, x, y});
                    const archive::PatchRecord& rec = part.records[size_t(at)];
                    readBlob(*open[size_t(sx)], rec, blob);
                    writer.copyPatch(rec, blob.data());
                    if (++written % 256 == 0)
                        reportProgress(progress, double(written) / double(g.patchCount()));
                }
        }
    }
    writer.setCodecTables(top.read(kTagTables, kMaxObservationBytes));
    writer.finish(info["metadata"].get<std::string>());
    reportDone(progress);
    MergeReport report;
    report.bytes = writer.bytesWritten();
    report.patches = written;
    report.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return report;
}

} // namespace ridge
