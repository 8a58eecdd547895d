// Every field of a plan file, checked for type and range (shard_internal.h, PlanReader).
#include "shard_internal.h"

#include "ridge/codec/codec_registry.h"
#include "ridge/core/error.h"

#include <nlohmann/json.hpp>

#include <cstdlib>
#include <limits>

namespace ridge::shard_internal {

namespace {

using nlohmann::json;

// Reads fields of one JSON object, naming "PLAN: FIELD" in every complaint.
class Fields {
  public:
    Fields(const std::string& path, const json& object, std::string prefix)
        : path_(path), object_(object), prefix_(std::move(prefix))
    {
        if (!object_.is_object())
            fail("", "is not an object");
    }

    [[noreturn]] void fail(const std::string& key, const std::string& what) const
    {
        throw Error(path_ + ": " + prefix_ + key + " " + what);
    }

    const json& at(const std::string& key) const
    {
        const auto it = object_.find(key);
        if (it == object_.end())
            fail(key, "is missing");
        return *it;
    }

    int64_t integer(const std::string& key, int64_t lo, int64_t hi) const
    {
        const json& v = at(key);
        if (!v.is_number_integer() || v.get<int64_t>() < lo || v.get<int64_t>() > hi)
            fail(key, "is not an integer in " + std::to_string(lo) + ".." + std::to_string(hi));
        return v.get<int64_t>();
    }

    uint64_t unsignedInteger(const std::string& key) const
    {
        const json& v = at(key);
        if (!v.is_number_unsigned())
            fail(key, "is not a non-negative integer");
        return v.get<uint64_t>();
    }

    std::string string(const std::string& key) const
    {
        const json& v = at(key);
        if (!v.is_string())
            fail(key, "is not a string");
        return v.get<std::string>();
    }

    bool boolean(const std::string& key) const
    {
        const json& v = at(key);
        if (!v.is_boolean())
            fail(key, "is not true or false");
        return v.get<bool>();
    }

    std::optional<double> number(const std::string& key) const
    {
        const json& v = at(key);
        if (v.is_null())
            return std::nullopt;
        if (!v.is_number() || !std::isfinite(v.get<double>()))
            fail(key, "is not a finite number or null");
        return v.get<double>();
    }

    // A finite number (null refused).
    std::optional<double> required(const std::string& key) const
    {
        const std::optional<double> v = number(key);
        if (!v)
            fail(key, "is null: a number is required");
        return v;
    }

    const std::string& path() const { return path_; }
    const std::string& prefix() const { return prefix_; }

    uint64_t hash(const std::string& key) const
    {
        const std::string text = string(key);
        char* end = nullptr;
        const unsigned long long v = std::strtoull(text.c_str(), &end, 16);
        if (text.size() != 16 || *end != '\0' ||
            text.find_first_not_of("0123456789abcdef") != std::string::npos)
            fail(key, "is not 16 lower-case hexadecimal digits");
        return v;
    }

    io::PixelWindow window(const std::string& key) const
    {
        const json& v = at(key);
        if (!v.is_array() || v.size() != 4)
            fail(key, "is not [x, y, width, height]");
        int w[4];
        for (size_t i = 0; i < 4; ++i) {
            if (!v[i].is_number_integer() || v[i].get<int64_t>() < 0 ||
                v[i].get<int64_t>() > std::numeric_limits<int>::max())
                fail(key, "is not [x, y, width, height] of non-negative integers");
            w[i] = v[i].get<int>();
        }
        return {w[0], w[1], w[2], w[3]};
    }

  private:
    const std::string& path_;
    const json& object_;
    std::string prefix_;
};

io::VerticalShift parseShift(const Fields& f, const std::string& name)
{
    if (name == "auto")
        return io::VerticalShift::Auto;
    if (name == "ellipsoid")
        return io::VerticalShift::Ellipsoid;
    if (name == "none")
        return io::VerticalShift::None;
    f.fail("vertical_shift", "is '" + name + "': must be auto, ellipsoid or none");
}

BuildOptions readOptions(const Fields& b)
{
    BuildOptions o;
    o.patch_size = int(b.integer("patch_size", 5, 4097));
    o.block_cells = int(b.integer("block_cells", 2, 4096));
    o.codec = b.string("codec");
    if (const std::string problem = codecSpecProblem(o.codec); !problem.empty())
        b.fail("codec", "'" + o.codec + "': " + problem);
    o.max_error = b.number("max_error");
    o.store_block_errors = b.boolean("store_block_errors");
    io::IngestOptions& i = o.ingest;
    i.band = int(b.integer("band", 1, io::IngestOptions::kMaxBand));
    if (const json& datum = b.at("vertical_datum"); !datum.is_null())
        i.vertical_datum = b.string("vertical_datum");
    i.vertical_shift = parseShift(b, b.string("vertical_shift"));
    i.spacing = b.number("spacing");
    i.force_spacing = b.boolean("force_spacing");
    i.z_scale = b.number("z_scale");
    i.z_offset = b.number("z_offset");
    try {
        i.fill_voids = io::parseVoidFill(b.string("fill_voids"));
    } catch (const Error& e) {
        b.fail("fill_voids", e.what());
    }
    i.sea_level = b.number("sea_level");
    i.max_error = b.number("quantization_max_error");
    if (const json& m = b.at("code_mapping"); !m.is_null()) {
        const Fields f(b.path(), m, b.prefix() + "code_mapping.");
        io::CodeMapping mapping;
        mapping.exact = f.boolean("exact");
        mapping.integer_origin = *f.required("integer_origin");
        mapping.max_code = f.integer("max_code", 1, 65535);
        mapping.quantization.scale = *f.required("scale");
        mapping.quantization.offset = *f.required("offset");
        mapping.quantization.max_error = *f.required("max_error");
        if (!(mapping.quantization.scale > 0) || !(mapping.quantization.max_error >= 0))
            f.fail("scale", "must be positive and max_error not negative");
        i.code_mapping = mapping;
    }
    try {
        o.validate();
    } catch (const Error& e) {
        b.fail("", std::string("options: ") + e.what());
    }
    return o;
}

} // namespace

PlanReader::PlanReader(std::string path, const std::string& text)
    : path_(std::move(path)), text_(text)
{
}

void PlanReader::read(ShardPlan& plan) const
{
    const json root = json::parse(text_, nullptr, false);
    if (root.is_discarded())
        throw Error(path_ + ": not a ridge plan: not JSON");
    const Fields top(path_, root, "");
    if (top.integer("ridge_plan", 0, 1 << 30) != 1)
        top.fail("ridge_plan", "is " + std::to_string(top.integer("ridge_plan", 0, 1 << 30)) +
                                   ": this ridge reads plan version 1");
    const Fields source(path_, top.at("source"), "source.");
    plan.source = source.string("path");
    plan.source_name = source.string("name");
    plan.data_type = source.string("data_type");
    plan.width = int(source.integer("width", 2, std::numeric_limits<int>::max()));
    plan.height = int(source.integer("height", 2, std::numeric_limits<int>::max()));
    plan.options = readOptions(Fields(path_, top.at("build"), "build."));
    plan.shard_level = int(top.integer("shard_level", 0, 31));
    plan.level_count = int(top.integer("level_count", 1, 32));
    try {
        const PyramidGeometry g = plan.geometry();
        if (plan.shard_level > g.finestLevel())
            top.fail("shard_level", "is below the finest level " + std::to_string(g.finestLevel()));
    } catch (const Error& e) {
        if (std::string(e.what()).rfind(path_, 0) == 0)
            throw;
        top.fail("level_count", std::string("does not fit the source: ") + e.what());
    }
    const json& inputs = top.at("inputs");
    if (!inputs.is_array())
        top.fail("inputs", "is not an array");
    for (size_t k = 0; k < inputs.size(); ++k) {
        const Fields in(path_, inputs[k], "inputs[" + std::to_string(k) + "].");
        PlanInput input;
        input.path = in.string("path");
        input.bytes = in.unsignedInteger("bytes");
        input.mtime_ns = in.integer("mtime_ns", std::numeric_limits<int64_t>::min(),
                                    std::numeric_limits<int64_t>::max());
        input.content = in.hash("fnv1a64");
        input.footprint = in.window("footprint");
        plan.inputs.push_back(std::move(input));
    }
    const json& shards = top.at("shards");
    if (!shards.is_array())
        top.fail("shards", "is not an array");
    for (size_t k = 0; k < shards.size(); ++k) {
        const Fields s(path_, shards[k], "shards[" + std::to_string(k) + "].");
        PlanShard shard;
        shard.id = s.integer("id", 0, std::numeric_limits<int32_t>::max());
        const json& r = s.at("root");
        if (!r.is_array() || r.size() != 3 || !r[0].is_number_integer() ||
            !r[1].is_number_integer() || !r[2].is_number_integer())
            s.fail("root", "is not [level, x, y]");
        shard.root = {r[0].get<int>(), r[1].get<int>(), r[2].get<int>()};
        shard.window = s.window("window");
        const json& in = s.at("inputs");
        if (!in.is_array())
            s.fail("inputs", "is not an array");
        for (const json& v : in) {
            if (!v.is_number_integer())
                s.fail("inputs", "holds a value that is not an input index");
            shard.inputs.push_back(v.get<int>());
        }
        shard.hash = s.hash("hash");
        plan.shards.push_back(std::move(shard));
    }
    plan.layout_hash = top.hash("layout_hash");
    plan.hash = top.hash("hash");
}

} // namespace ridge::shard_internal
