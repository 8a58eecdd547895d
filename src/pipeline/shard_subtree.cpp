// A shard's window and its subtree's bounds (shard_internal.h), and what the steps share.
#include "shard_internal.h"

#include "ridge/core/crc32.h"
#include "ridge/core/error.h"
#include "ridge/core/file_io.h"
#include "ridge/pyramid/patch_context.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <sys/resource.h>
#include <sys/stat.h>

namespace ridge::shard_internal {

namespace {

int64_t ceilDiv(int64_t a, int64_t b)
{
    return (a + b - 1) / b;
}

// Refuses an input whose size or modification time differ from the plan's.
void checkInputsUnchanged(const ShardPlan& plan, const PlanShard& shard)
{
    for (int k : shard.inputs) {
        const PlanInput& in = plan.inputs[size_t(k)];
        struct stat st {};
        const bool same =
            ::stat(in.path.c_str(), &st) == 0 && uint64_t(st.st_size) == in.bytes &&
            int64_t(st.st_mtim.tv_sec) * 1000000000 + st.st_mtim.tv_nsec == in.mtime_ns;
        if (!same)
            throw Error("shard " + std::to_string(shard.id) + ": input " + in.path +
                        " is missing or has changed since the plan was made (size or "
                        "modification time); run `ridge plan` again");
    }
}

} // namespace

io::PixelWindow subtreeWindow(const PyramidGeometry& g, PatchId root)
{
    const int64_t span = int64_t{g.cells()} * g.step(root.level);
    const int64_t x0 = root.x * span, y0 = root.y * span;
    const int64_t x1 = std::min<int64_t>(x0 + span, g.width() - 1);
    const int64_t y1 = std::min<int64_t>(y0 + span, g.height() - 1);
    return {int(x0), int(y0), int(x1 - x0 + 1), int(y1 - y0 + 1)};
}

uint64_t hashBytes(const std::vector<uint8_t>& bytes)
{
    return fnv1a64(bytes.data(), bytes.size());
}

uint64_t summaryKey(const PlanShard& shard)
{
    const uint64_t words[2] = {shard.hash, 1};
    return fnv1a64(words, sizeof words);
}

uint64_t observationKey(const PlanShard& shard, uint64_t top_state)
{
    const uint64_t words[3] = {shard.hash, 2, top_state};
    return fnv1a64(words, sizeof words);
}

uint64_t segmentKey(const PlanShard& shard, uint64_t top_state, const uint16_t* parent, int n)
{
    const uint64_t words[4] = {shard.hash, 4, top_state,
                               parent ? fnv1a64(parent, sizeof(uint16_t) * size_t(n) * n) : 0};
    return fnv1a64(words, sizeof words);
}

BlobSink::BlobSink(archive::ShardFileWriter& out) : out_(out)
{
    out_.beginSection(kTagBlobs);
}

void BlobSink::add(build_stages::EncodedPatch& e)
{
    archive::PatchRecord& rec = e.record;
    rec.offset = out_.sectionPosition();
    rec.block_errors_size = uint32_t(e.block_errors.size());
    rec.size = uint32_t(e.block_errors.size() + e.validity.size() + e.sample_flags.size() +
                        e.payload.size());
    uint32_t crc = 0;
    for (const std::vector<uint8_t>* part :
         {&e.block_errors, &e.validity, &e.sample_flags, &e.payload}) {
        crc = crc32(part->data(), part->size(), crc);
        out_.append(part->data(), part->size());
    }
    rec.crc32 = crc;
    uint8_t entry[archive::kIndexEntrySize];
    archive::serializeRecord(rec, entry);
    records_.insert(records_.end(), entry, entry + archive::kIndexEntrySize);
}

void BlobSink::finish()
{
    out_.endSection();
    out_.addSection(kTagRecords, records_);
}

nlohmann::json readInfo(const archive::ShardFileReader& file)
{
    const std::vector<uint8_t> bytes = file.read(kTagInfo, kMaxInfoBytes);
    nlohmann::json info = nlohmann::json::parse(bytes.begin(), bytes.end(), nullptr, false);
    if (!info.is_object())
        throw Error(file.path() + ": INFO section is not a JSON object");
    return info;
}

uint64_t peakRss()
{
    struct rusage usage {};
    ::getrusage(RUSAGE_SELF, &usage);
    return uint64_t(usage.ru_maxrss) * 1024;
}

build_stages::BuildContext planContext(const ShardPlan& plan)
{
    const io::CodeRowReader source(plan.source, plan.options.ingest);
    if (source.width() != plan.width || source.height() != plan.height)
        throw Error(plan.source + ": is " + std::to_string(source.width()) + "x" +
                    std::to_string(source.height()) + ", the plan says " +
                    std::to_string(plan.width) + "x" + std::to_string(plan.height) +
                    ": it changed since the plan was made");
    build_stages::BuildContext ctx = build_stages::makeContext(
        plan.width, plan.height, source.quantization(), source.geo(), plan.options);
    if (ctx.geometry.levelCount() != plan.level_count)
        throw Error(plan.path + ": internal error: level count");
    return ctx;
}

void restoreCodec(build_stages::BuildContext& ctx, const archive::ShardFileReader& top)
{
    const std::vector<uint8_t> state = top.read(kTagCodec, kMaxObservationBytes);
    try {
        ctx.codec->restoreTraining(state.data(), state.size());
    } catch (const Error& e) {
        throw Error(top.path() + ": " + e.what());
    }
}

SubtreeLayout::SubtreeLayout(const PyramidGeometry& g, PatchId root) : g_(&g), root_(root)
{
    first_.push_back(0);
    for (int l = root.level; l < g.levelCount(); ++l)
        first_.push_back(first_.back() + count(l));
}

int SubtreeLayout::endX(int l) const
{
    return std::min((root_.x + 1) << (l - root_.level), g_->patchesX(l));
}

int SubtreeLayout::endY(int l) const
{
    return std::min((root_.y + 1) << (l - root_.level), g_->patchesY(l));
}

PatchId SubtreeLayout::patchAt(int l, int64_t k) const
{
    return {l, firstX(l) + int(k % columns(l)), firstY(l) + int(k / columns(l))};
}

int64_t SubtreeLayout::position(PatchId p) const
{
    if (p.level < root_.level || p.level >= g_->levelCount() || p.x < firstX(p.level) ||
        p.x >= endX(p.level) || p.y < firstY(p.level) || p.y >= endY(p.level))
        return -1;
    const PatchId at = local(p);
    return firstPosition(p.level) + int64_t(at.y) * columns(p.level) + at.x;
}

Subtree::Subtree(const ShardPlan& plan, int64_t id)
    : shard_(plan.shard(id)), g_(plan.geometry()), layout_(g_, shard_.root)
{
    checkInputsUnchanged(plan, shard_);
    const io::PixelWindow& w = shard_.window;
    const io::RasterWindow source_window(plan.source, w);
    io::CodeRowReader reader(source_window.path(), plan.options.ingest);
    if (reader.width() != w.width || reader.height() != w.height)
        throw Error("shard " + std::to_string(id) + ": internal error: window size");
    window_.width = w.width;
    window_.height = w.height;
    window_.codes.resize(size_t(w.width) * w.height);
    if (reader.flagsWater())
        flags_.resize(window_.codes.size());
    const int64_t voids = reader.readRows(0, w.height, window_.codes.data(),
                                          flags_.empty() ? nullptr : flags_.data());
    if (voids > 0)
        throw Error("shard " + std::to_string(id) + ": " + std::to_string(voids) +
                    " nodata samples in its window " + std::to_string(w.x) + "," +
                    std::to_string(w.y) + " " + std::to_string(w.width) + "x" +
                    std::to_string(w.height) +
                    ": sharded builds need void-free input (fill it first, e.g. gdal_fillnodata, "
                    "or build it in one process)");
    samples_read = int64_t(window_.codes.size());
    // The source's heights (not their codes'), as `ridge build` states them: a shared sample
    // counted twice changes neither extreme.
    min_metres = reader.stats().min_metres;
    max_metres = reader.stats().max_metres;

    // The samples this shard owns: all but the shared east column and south row, unless they
    // are the raster's last.
    const int own_w = w.x + w.width == plan.width ? w.width : w.width - 1;
    const int own_h = w.y + w.height == plan.height ? w.height : w.height - 1;
    for (int y = 0; y < own_h; ++y) {
        if (!flags_.empty())
            owned_water += std::count_if(flags_.data() + size_t(y) * w.width,
                                         flags_.data() + size_t(y) * w.width + own_w,
                                         [](uint8_t f) { return f != 0; });
    }
    owned_samples = int64_t(own_w) * own_h;

    const int k = shard_.root.level;
    const int64_t first = layout_.total();
    for (int l = k; l < g_.levelCount(); ++l) {
        const int64_t step = g_.step(l);
        views_.push_back({window_.codes.data(), w.width, w.height, step,
                          int(ceilDiv(w.width - 1, step) + 1),
                          int(ceilDiv(w.height - 1, step) + 1)});
    }
    errors_.err_int.assign(size_t(first), 0.f);
    errors_.err_appr.assign(size_t(first), 0.f);
    errors_.min_code.assign(size_t(first), 0);
    errors_.max_code.assign(size_t(first), 0);

    // Err_Int and ranges of every patch (measurePatches' rule), then Err_Appr bottom up
    // (accumulatePatchErrors'): the same values the whole raster's pyramid gives them.
    const int n = g_.patchSize();
    build_stages::parallelFor(first, 4, [&](int64_t index) {
        thread_local std::vector<uint16_t> samples;
        samples.resize(size_t(n) * n);
        int l = k;
        while (index >= layout_.firstPosition(l) + layout_.count(l))
            ++l;
        const PatchId p = layout_.patchAt(l, index - layout_.firstPosition(l));
        const PatchId at = layout_.local(p);
        extractPatch(view(l), n, at, samples.data());
        const auto [lo, hi] = std::minmax_element(samples.begin(), samples.end());
        errors_.min_code[size_t(index)] = *lo;
        errors_.max_code[size_t(index)] = *hi;
        if (l < g_.finestLevel())
            errors_.err_int[size_t(index)] =
                float(interpolationError(samples.data(), view(l + 1), n, at));
    });
    for (int l = g_.finestLevel() - 1; l >= k; --l)
        for (int64_t j = 0; j < layout_.count(l); ++j) {
            const PatchId p = layout_.patchAt(l, j);
            const int64_t index = layout_.position(p);
            float worst_child = 0.f;
            for (int c = 0; c < 4; ++c) {
                const PatchId child{l + 1, 2 * p.x + (c & 1), 2 * p.y + (c >> 1)};
                if (!g_.exists(child))
                    continue;
                const int64_t ci = layout_.position(child);
                worst_child = std::max(worst_child, errors_.err_appr[size_t(ci)]);
                errors_.min_code[size_t(index)] =
                    std::min(errors_.min_code[size_t(index)], errors_.min_code[size_t(ci)]);
                errors_.max_code[size_t(index)] =
                    std::max(errors_.max_code[size_t(index)], errors_.max_code[size_t(ci)]);
            }
            errors_.err_appr[size_t(index)] = errors_.err_int[size_t(index)] + worst_child;
        }
}

build_stages::PatchSummary Subtree::summary(PatchId p) const
{
    const size_t i = size_t(layout_.position(p));
    return {errors_.min_code[i], errors_.max_code[i], errors_.err_appr[i]};
}

PatchSampleFlags Subtree::flags(PatchId p) const
{
    return build_stages::windowPatchFlags(flags_.data(), window_.width, window_.height,
                                          g_.step(p.level), g_.patchSize(), layout_.local(p));
}

} // namespace ridge::shard_internal
