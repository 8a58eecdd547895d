// `ridge plan`: the shards of a sharded build and the plan file (docs/FORMAT.md, "Shard plan").
#include "ridge/pipeline/shard.h"

#include "shard_internal.h"

#include "ridge/codec/codec_registry.h"
#include "ridge/core/atomic_output.h"
#include "ridge/core/error.h"
#include "ridge/core/file_identity.h"
#include "ridge/core/file_io.h"
#include "ridge/core/json_text.h"
#include "ridge/io/dataset_files.h"

#include <nlohmann/json.hpp>

#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <sys/stat.h>
#include <unistd.h>

namespace ridge {

namespace {

using nlohmann::json;
namespace fs = std::filesystem;

constexpr int kPlanVersion = 1;
// A plan larger than this is not one ridge wrote (26,000 GLO-30 shards take ~5 MB).
constexpr uint64_t kMaxPlanBytes = uint64_t{1} << 30;

std::string hex(uint64_t v)
{
    char text[17];
    std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(v));
    return text;
}

const char* shiftName(io::VerticalShift shift)
{
    switch (shift) {
    case io::VerticalShift::Ellipsoid:
        return "ellipsoid";
    case io::VerticalShift::None:
        return "none";
    case io::VerticalShift::Auto:
        break;
    }
    return "auto";
}

template <typename T> json optional(const std::optional<T>& v)
{
    return v ? json(*v) : json(nullptr);
}

json mappingJson(const std::optional<io::CodeMapping>& m)
{
    if (!m)
        return nullptr;
    return {{"exact", m->exact},
            {"integer_origin", m->integer_origin},
            {"max_code", m->max_code},
            {"scale", m->quantization.scale},
            {"offset", m->quantization.offset},
            {"max_error", m->quantization.max_error}};
}

json optionsJson(const BuildOptions& o)
{
    const io::IngestOptions& i = o.ingest;
    return {{"patch_size", o.patch_size},
            {"block_cells", o.block_cells},
            {"codec", o.codec},
            {"max_error", optional(o.max_error)},
            {"store_block_errors", o.store_block_errors},
            {"band", i.band},
            {"vertical_datum", optional(i.vertical_datum)},
            {"vertical_shift", shiftName(i.vertical_shift)},
            {"spacing", optional(i.spacing)},
            {"force_spacing", i.force_spacing},
            {"z_scale", optional(i.z_scale)},
            {"z_offset", optional(i.z_offset)},
            {"fill_voids", io::voidFillName(i.fill_voids)},
            {"sea_level", optional(i.sea_level)},
            {"quantization_max_error", optional(i.max_error)},
            {"code_mapping", mappingJson(i.code_mapping)}};
}

json windowJson(const io::PixelWindow& w)
{
    return json::array({w.x, w.y, w.width, w.height});
}

// What every shard file of the plan carries: a change here makes every shard file stale.
uint64_t layoutHash(const ShardPlan& plan)
{
    json shards = json::array();
    for (const PlanShard& s : plan.shards)
        shards.push_back({s.id, windowJson(s.window)});
    const json layout = {{"build", optionsJson(plan.options)},
                         {"source", {plan.source_name, plan.data_type, plan.width, plan.height}},
                         {"shard_level", plan.shard_level},
                         {"level_count", plan.level_count},
                         {"shards", shards}};
    const std::string text = layout.dump();
    return fnv1a64(text.data(), text.size());
}

uint64_t shardHash(const ShardPlan& plan, const PlanShard& shard)
{
    std::vector<uint64_t> words{plan.layout_hash, uint64_t(shard.id)};
    for (int k : shard.inputs) {
        const PlanInput& in = plan.inputs[size_t(k)];
        words.push_back(in.content);
        for (int v : {in.footprint.x, in.footprint.y, in.footprint.width, in.footprint.height})
            words.push_back(uint64_t(uint32_t(v)));
    }
    return fnv1a64(words.data(), words.size() * sizeof(uint64_t));
}

uint64_t planHash(const ShardPlan& plan)
{
    std::vector<uint64_t> words{plan.layout_hash};
    for (const PlanShard& s : plan.shards)
        words.push_back(s.hash);
    return fnv1a64(words.data(), words.size() * sizeof(uint64_t));
}

// The file's bytes hashed in 1 MiB reads.
uint64_t contentHash(const std::string& path, uint64_t* bytes, int64_t* mtime_ns)
{
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0)
        throw Error(path + ": cannot open: " + std::strerror(errno));
    struct stat st {};
    if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        ::close(fd);
        throw Error(path + ": not a regular file (a plan's inputs are files)");
    }
    *bytes = uint64_t(st.st_size);
    *mtime_ns = int64_t(st.st_mtim.tv_sec) * 1000000000 + st.st_mtim.tv_nsec;
    // FNV-1a over the whole file, chained through 1 MiB blocks' hashes.
    std::vector<uint8_t> block(1 << 20);
    std::vector<uint64_t> words;
    for (uint64_t at = 0; at < *bytes; at += block.size()) {
        const size_t n = size_t(std::min<uint64_t>(block.size(), *bytes - at));
        readAllAt(fd, block.data(), n, at, path);
        words.push_back(fnv1a64(block.data(), n));
    }
    ::close(fd);
    return fnv1a64(words.data(), words.size() * sizeof(uint64_t));
}

std::vector<PlanShard> planShards(const PyramidGeometry& g, int k)
{
    std::vector<PlanShard> shards;
    for (int y = 0; y < g.patchesY(k); ++y)
        for (int x = 0; x < g.patchesX(k); ++x) {
            PlanShard s;
            s.id = int64_t(y) * g.patchesX(k) + x;
            s.root = {k, x, y};
            s.window = shard_internal::subtreeWindow(g, s.root);
            shards.push_back(std::move(s));
        }
    return shards;
}

json planJson(const ShardPlan& plan)
{
    json inputs = json::array();
    for (const PlanInput& in : plan.inputs)
        inputs.push_back({{"path", in.path},
                          {"bytes", in.bytes},
                          {"mtime_ns", in.mtime_ns},
                          {"fnv1a64", hex(in.content)},
                          {"footprint", windowJson(in.footprint)}});
    json shards = json::array();
    for (const PlanShard& s : plan.shards)
        shards.push_back({{"id", s.id},
                          {"root", {s.root.level, s.root.x, s.root.y}},
                          {"window", windowJson(s.window)},
                          {"inputs", s.inputs},
                          {"hash", hex(s.hash)}});
    return {{"ridge_plan", kPlanVersion},
            {"source",
             {{"path", plan.source},
              {"name", plan.source_name},
              {"data_type", plan.data_type},
              {"width", plan.width},
              {"height", plan.height}}},
            {"inputs", inputs},
            {"build", optionsJson(plan.options)},
            {"shard_level", plan.shard_level},
            {"level_count", plan.level_count},
            {"shards", shards},
            {"layout_hash", hex(plan.layout_hash)},
            {"hash", hex(plan.hash)}};
}

} // namespace

PyramidGeometry ShardPlan::geometry() const
{
    return PyramidGeometry::fromStored(width, height, options.patch_size, level_count);
}

const PlanShard& ShardPlan::shard(int64_t id) const
{
    if (id < 0 || id >= int64_t(shards.size()))
        throw Error(path + ": no shard " + std::to_string(id) + " (0.." +
                    std::to_string(int64_t(shards.size()) - 1) + ")");
    return shards[size_t(id)];
}

ShardPlan makePlan(const std::vector<std::string>& inputs, const BuildOptions& options,
                   int shard_level, const std::string& plan_path)
{
    options.validate();
    if (inputs.empty())
        throw Error(plan_path + ": a plan needs at least one input");
    if (options.filter != PyramidFilter::Decimate)
        throw Error("--filter " + std::string(filterName(options.filter)) +
                    ": sharded builds take the decimation filter only (Neville's support "
                    "crosses shard edges)");
    if (!options.ingest.water_layer.empty())
        throw Error("--water " + options.ingest.water_layer +
                    ": sharded builds do not take a water layer yet (--sea-level works)");
    if (const std::string problem = codecSpecProblem(options.codec); !problem.empty())
        throw Error("codec '" + options.codec + "': " + problem);

    ShardPlan plan;
    plan.options = options;
    plan.options.memory_limit_bytes = 0;
    plan.options.progress = {};
    plan.path = plan_path;
    plan.shard_level = shard_level;
    std::vector<std::string> absolute;
    for (const std::string& input : inputs)
        absolute.push_back(fs::absolute(input).lexically_normal().string());
    if (inputs.size() == 1) {
        plan.source = absolute[0];
        plan.source_name = shard_internal::recordedSourceName(inputs[0]);
    } else {
        fs::path vrt = fs::absolute(plan_path).lexically_normal();
        vrt.replace_extension(".vrt");
        refuseOutputOverInput(vrt.string(), absolute);
        io::buildMosaic(absolute, vrt.string());
        plan.source = vrt.string();
        plan.source_name = vrt.filename().string();
    }
    const io::RasterProbe probe = io::probeRaster(plan.source, options.ingest);
    {
        // Other types than 8/16-bit integers: the codes are settled here, over the whole
        // raster (a survey and an error pass, as `ridge build` makes them), and every shard
        // reads its window through this mapping.
        io::IngestOptions ingest = options.ingest;
        ingest.code_mapping.reset();
        const io::CodeRowReader reader(plan.source, ingest);
        if (reader.geo().vertical_shift)
            throw Error(plan.source +
                        ": its heights would be shifted to the ellipsoid, which sharded builds "
                        "do not do yet; --novshift keeps them as they are");
        plan.options.ingest.code_mapping = reader.codeMapping();
    }
    plan.data_type = probe.data_type;
    plan.width = probe.width;
    plan.height = probe.height;
    const PyramidGeometry g(plan.width, plan.height, options.patch_size);
    plan.level_count = g.levelCount();
    if (shard_level < 0 || shard_level > g.finestLevel())
        throw Error("--shard-level " + std::to_string(shard_level) + ": must be 0.." +
                    std::to_string(g.finestLevel()) + " for this " + std::to_string(plan.width) +
                    "x" + std::to_string(plan.height) + " raster in patches of " +
                    std::to_string(options.patch_size));

    // The files under each shard: a mosaic's inputs where they lie; a single raster's files
    // (and side-cars) everywhere.
    std::vector<io::MosaicPart> parts;
    if (inputs.size() == 1) {
        for (const std::string& file : io::datasetFiles(plan.source))
            parts.push_back({file, {0, 0, plan.width, plan.height}});
    } else {
        parts = io::mosaicParts(plan.source, absolute);
    }
    for (const io::MosaicPart& part : parts) {
        PlanInput in;
        in.path = fs::absolute(part.path).lexically_normal().string();
        in.content = contentHash(in.path, &in.bytes, &in.mtime_ns);
        in.footprint = part.footprint;
        plan.inputs.push_back(std::move(in));
    }
    plan.shards = planShards(g, shard_level);
    plan.layout_hash = layoutHash(plan);
    for (PlanShard& s : plan.shards) {
        for (size_t k = 0; k < plan.inputs.size(); ++k)
            if (plan.inputs[k].footprint.intersects(s.window))
                s.inputs.push_back(int(k));
        s.hash = shardHash(plan, s);
    }
    plan.hash = planHash(plan);

    refuseOutputOverInput(plan_path, absolute);
    const std::string text = planJson(plan).dump(1) + "\n";
    AtomicOutput out(plan_path);
    writeAll(out.fd(), text.data(), text.size(), plan_path);
    out.commit();
    return plan;
}

ShardPlan loadPlan(const std::string& plan_path)
{
    ShardPlan plan;
    plan.path = plan_path;
    std::ifstream file(plan_path, std::ios::binary);
    if (!file)
        throw Error(plan_path + ": cannot open: " + std::strerror(errno));
    std::ostringstream text;
    text << file.rdbuf();
    if (text.str().size() > kMaxPlanBytes)
        throw Error(plan_path + ": larger than any plan (1 GiB)");
    shard_internal::PlanReader r(plan_path, text.str());
    r.read(plan);
    // Structure before hashes, so that a hand-edited plan is told what is wrong with it.
    const PyramidGeometry g = plan.geometry();
    const std::vector<PlanShard> expected = planShards(g, plan.shard_level);
    if (plan.shards.size() != expected.size()) {
        std::vector<bool> seen(expected.size(), false);
        for (const PlanShard& s : plan.shards)
            if (s.id >= 0 && s.id < int64_t(seen.size()))
                seen[size_t(s.id)] = true;
        for (size_t id = 0; id < seen.size(); ++id)
            if (!seen[id])
                throw Error(plan_path + ": shard " + std::to_string(id) +
                            " is missing: the plan has " + std::to_string(plan.shards.size()) +
                            " shards, level " + std::to_string(plan.shard_level) + " has " +
                            std::to_string(expected.size()) + " patches");
        throw Error(plan_path + ": " + std::to_string(plan.shards.size()) + " shards, level " +
                    std::to_string(plan.shard_level) + " has " + std::to_string(expected.size()) +
                    " patches (a shard is listed twice)");
    }
    for (size_t k = 0; k < expected.size(); ++k) {
        const PlanShard& s = plan.shards[k];
        const PlanShard& e = expected[k];
        if (s.id != e.id)
            throw Error(plan_path + ": shards[" + std::to_string(k) + "] is shard " +
                        std::to_string(s.id) + ", expected " + std::to_string(e.id) +
                        " (shards are listed once each, in id order)");
        if (!(s.root == e.root) || !(s.window == e.window))
            throw Error(plan_path + ": shard " + std::to_string(s.id) +
                        ": its root or window is not its level-" +
                        std::to_string(plan.shard_level) +
                        " patch's footprint (shards would overlap or leave a gap)");
        for (int in : s.inputs)
            if (in < 0 || in >= int(plan.inputs.size()))
                throw Error(plan_path + ": shard " + std::to_string(s.id) + ": input " +
                            std::to_string(in) + " does not exist");
    }
    const uint64_t stored_layout = plan.layout_hash, stored_hash = plan.hash;
    plan.layout_hash = layoutHash(plan);
    if (plan.layout_hash != stored_layout)
        throw Error(plan_path + ": layout_hash does not match the plan's options and shards: "
                                "it was edited after `ridge plan` wrote it; plan again");
    for (const PlanShard& s : plan.shards)
        if (shardHash(plan, s) != s.hash)
            throw Error(plan_path + ": shard " + std::to_string(s.id) +
                        ": hash does not match its inputs: the plan was edited; plan again");
    if (planHash(plan) != stored_hash)
        throw Error(plan_path + ": hash does not match: the plan was edited; plan again");
    return plan;
}

} // namespace ridge
