#include "ridge/archive/archive_metadata.h"

#include "ridge/codec/codec_registry.h"
#include "ridge/core/error.h"
#include "ridge/core/parameter_check.h"
#include "ridge/pyramid/level_pyramid.h"

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>

namespace ridge::archive {

namespace {

using nlohmann::json;

[[noreturn]] void reject(const std::string& problem)
{
    throw Error("metadata: " + problem);
}

// Cuts `text` to at most `size` bytes without splitting a UTF-8 sequence (the parser has
// checked that the document is UTF-8, so a message quoting it stays UTF-8 and can itself be
// emitted as JSON, by `verify --json`).
std::string_view utf8Prefix(std::string_view text, size_t size)
{
    if (text.size() <= size)
        return text;
    while (size > 0 && (static_cast<unsigned char>(text[size]) & 0xC0) == 0x80)
        --size;
    return text.substr(0, size);
}

// Appends the compact JSON text of `value` to `out` until `out` holds more than `budget`
// bytes, then stops: every level of nesting writes a byte before it descends, so the
// recursion is at most `budget` deep and the work O(budget) whatever the value's size.
void appendExcerpt(const json& value, size_t budget, std::string& out)
{
    if (out.size() > budget)
        return;
    switch (value.type()) {
    case json::value_t::array:
        out += '[';
        for (auto it = value.begin(); it != value.end() && out.size() <= budget; ++it) {
            if (it != value.begin())
                out += ',';
            appendExcerpt(*it, budget, out);
        }
        out += ']';
        return;
    case json::value_t::object:
        out += '{';
        for (auto it = value.begin(); it != value.end() && out.size() <= budget; ++it) {
            if (it != value.begin())
                out += ',';
            out += json(std::string(utf8Prefix(it.key(), budget))).dump();
            out += ':';
            appendExcerpt(it.value(), budget, out);
        }
        out += '}';
        return;
    case json::value_t::string:
        // Only the part that can show: a 10 MB string is not copied for a 40-byte message.
        out +=
            json(std::string(utf8Prefix(value.get_ref<const std::string&>(), budget + 1))).dump();
        return;
    default: // numbers, booleans, null: short
        out += value.dump();
        return;
    }
}

// A JSON value as messages quote it: numbers as formatNumber prints them, anything else as
// its compact JSON text cut to 40 bytes. Bounded: never serialises more than that of a value
// nested or long without limit (100,000 nested arrays crashed the recursive dump).
std::string quote(const json& value)
{
    if (value.is_number())
        return formatNumber(value.get<double>());
    constexpr size_t kShown = 40;
    std::string text;
    appendExcerpt(value, kShown, text);
    if (text.size() > kShown)
        text = std::string(utf8Prefix(text, kShown - 3)) + "...";
    return text;
}

// One object of the document, read key by key; every failure names "section.key".
class Section {
  public:
    Section(const json& object, std::string name) : object_(object), name_(std::move(name)) {}

    // "key" at the top level, else "section.key".
    std::string path(const char* key) const { return name_.empty() ? key : name_ + "." + key; }

    const json* find(const char* key) const
    {
        const auto it = object_.find(key);
        return it == object_.end() ? nullptr : &*it;
    }
    const json& require(const char* key) const
    {
        const json* value = find(key);
        if (!value)
            reject(path(key) + " is missing");
        return *value;
    }

    Section section(const char* key) const
    {
        const json& value = require(key);
        if (!value.is_object())
            reject(path(key) + " is " + quote(value) + ": must be an object");
        return {value, path(key)};
    }
    std::string string(const char* key) const { return stringValue(key, require(key)); }
    std::optional<std::string> optionalString(const char* key) const
    {
        const json* value = find(key);
        return value ? std::optional(stringValue(key, *value)) : std::nullopt;
    }
    bool boolean(const char* key) const
    {
        const json& value = require(key);
        if (!value.is_boolean())
            reject(path(key) + " is " + quote(value) + ": must be true or false");
        return value.get<bool>();
    }
    // An integer in [lo, hi] (JSON integers only: 301.0 is not one).
    int64_t integer(const char* key, int64_t lo, int64_t hi) const
    {
        const json& value = require(key);
        if (!value.is_number_integer())
            reject(path(key) + " is " + quote(value) + ": must be an integer");
        const bool huge = value.is_number_unsigned() &&
                          value.get<uint64_t>() > uint64_t(std::numeric_limits<int64_t>::max());
        const int64_t v = huge ? std::numeric_limits<int64_t>::max() : value.get<int64_t>();
        if (huge || v < lo || v > hi)
            reject(path(key) + " is " + value.dump() + ": must be an integer in [" +
                   std::to_string(lo) + ", " + std::to_string(hi) + "]");
        return v;
    }
    double number(const char* key, ValueRange range = ValueRange::any()) const
    {
        return numberValue(path(key), require(key), range);
    }
    std::optional<double> optionalNumber(const char* key, ValueRange range) const
    {
        const json* value = find(key);
        return value ? std::optional(numberValue(path(key), *value, range)) : std::nullopt;
    }
    // A number in `range`. The parser already refuses numbers beyond f64 (1e999); the range
    // check still refuses non-finite ones, as everywhere.
    static double numberValue(const std::string& name, const json& value, ValueRange range)
    {
        if (!value.is_number())
            reject(name + " is " + quote(value) + ": must be a number");
        const double v = value.get<double>();
        if (!range.contains(v))
            reject(name + " is " + formatNumber(v) + ": must be " + range.describe());
        return v;
    }

  private:
    std::string stringValue(const char* key, const json& value) const
    {
        if (!value.is_string())
            reject(path(key) + " is " + quote(value) + ": must be a string");
        return value.get<std::string>();
    }

    const json& object_;
    std::string name_;
};

// Refuses "NAME is VALUE but the header's FIELD is HEADER" unless they agree.
void expectHeader(const std::string& name, int64_t value, uint32_t header, const char* field)
{
    if (value != int64_t{header})
        reject(name + " is " + std::to_string(value) + " but the header's " + field + " is " +
               std::to_string(header));
}

// GDAL's most bands in one dataset (IngestOptions::kMaxBand).
constexpr int64_t kMaxBand = 65536;

SourceMetadata parseSource(const Section& s, const Header& header)
{
    SourceMetadata m;
    m.path = s.string("path");
    m.data_type = s.string("data_type");
    if (s.find("band"))
        m.band = static_cast<int>(s.integer("band", 1, kMaxBand));
    constexpr int64_t kMaxInt = std::numeric_limits<int64_t>::max();
    m.width = s.integer("width", 0, kMaxInt);
    expectHeader(s.path("width"), m.width, header.width, "width");
    m.height = s.integer("height", 0, kMaxInt);
    expectHeader(s.path("height"), m.height, header.height, "height");
    // Not bounded by width·height: streamed builds before December 2026 counted the source rows
    // that two strips share twice (CodeRowReader::stats, fixed since), and those archives
    // must open.
    m.valid_samples = s.integer("valid_samples", 0, kMaxInt);
    const int64_t samples = m.width * m.height; // both < 2^32: no overflow
    m.voids_filled = s.integer("voids_filled", 0, samples);
    // Version 2 (kept nodata): both keys, their sum within the grid. Version 1 archives
    // filled every void and have neither.
    if (header.version >= kFirstVersionWithValidity || s.find("voids_kept") ||
        s.find("fill_voids")) {
        m.voids_kept = s.integer("voids_kept", 0, samples - m.voids_filled);
        m.fill_voids = s.string("fill_voids");
        if (m.fill_voids != "all" && m.fill_voids != "interior" && m.fill_voids != "none")
            reject(s.path("fill_voids") + " is \"" + m.fill_voids +
                   "\": must be \"all\", \"interior\" or \"none\"");
        if (m.fill_voids == "all" && m.voids_kept != 0)
            reject(s.path("voids_kept") + " is " + std::to_string(m.voids_kept) + " but " +
                   s.path("fill_voids") + " is \"all\": must be 0");
    }
    m.void_fill = s.string("void_fill");
    m.nodata = s.optionalNumber("nodata", ValueRange::any());
    m.min_metres = s.number("min_metres");
    m.max_metres = s.number("max_metres");
    if (!(m.min_metres <= m.max_metres))
        reject(s.path("min_metres") + " " + formatNumber(m.min_metres) + " > " +
               s.path("max_metres") + " " + formatNumber(m.max_metres));
    m.exact = s.boolean("exact");
    // Exact ingest represents every valid sample by its code's height: no quantization error.
    if (m.exact && header.quantization_error != 0)
        reject(s.path("exact") + " is true but the header's quantization_error is " +
               formatNumber(header.quantization_error));
    return m;
}

// A geotransform every command can use: pixels of non-zero area whose inverse is finite
// (query, info's corners and extract's windows map coordinates to pixels), and every corner
// of the grid finite (extract writes them). GDALInvGeoTransform's algebra.
void checkGeotransform(const std::string& name, const std::array<double, 6>& g,
                       const Header& header)
{
    const double det = g[1] * g[5] - g[2] * g[4];
    if (!(std::abs(det) > 0.0) || !std::isfinite(det) || !std::isfinite(1.0 / det))
        reject(name + " is [" + formatNumber(g[0]) + "," + formatNumber(g[1]) + "," +
               formatNumber(g[2]) + "," + formatNumber(g[3]) + "," + formatNumber(g[4]) + "," +
               formatNumber(g[5]) + "]: its pixels have zero area (determinant " +
               formatNumber(det) + "): must map pixels to coordinates and back");
    const double w = header.width, h = header.height;
    for (const double x : {g[0] + w * g[1], g[0] + h * g[2], g[0] + w * g[1] + h * g[2]})
        for (const double y : {g[3] + w * g[4], g[3] + h * g[5], g[3] + w * g[4] + h * g[5]})
            if (!std::isfinite(x) || !std::isfinite(y))
                reject(name + ": the grid's corners are not finite (" + formatNumber(x) + ", " +
                       formatNumber(y) + ")");
}

GeoreferenceMetadata parseGeoreference(const Section& s, const Header& header)
{
    GeoreferenceMetadata m;
    m.crs_wkt = s.string("crs_wkt");
    m.geographic = s.boolean("geographic");
    m.vertical_units = s.string("vertical_units");
    m.spacing_from_user = s.boolean("spacing_from_user");
    if (const json* gt = s.find("geotransform")) {
        if (!gt->is_array() || gt->size() != 6)
            reject(s.path("geotransform") + " is " + quote(*gt) +
                   ": must be an array of 6 numbers (GDAL order)");
        std::array<double, 6> values;
        for (size_t k = 0; k < 6; ++k)
            values[k] = Section::numberValue(s.path("geotransform") + "[" + std::to_string(k) + "]",
                                             (*gt)[k], ValueRange::any());
        checkGeotransform(s.path("geotransform"), values, header);
        m.geotransform = values;
    }
    if (s.find("vertical_datum")) {
        const Section datum = s.section("vertical_datum");
        VerticalDatumMetadata d;
        d.name = datum.string("name");
        if (d.name.empty())
            reject(datum.path("name") + " is \"\": must name the datum");
        if (datum.find("epsg"))
            d.epsg = static_cast<int>(datum.integer("epsg", 1, std::numeric_limits<int>::max()));
        d.origin = datum.optionalString("from").value_or("");
        m.vertical_datum = d;
    }
    return m;
}

BuildMetadata parseBuild(const Section& s, const Header& header)
{
    BuildMetadata m;
    m.patch_size = static_cast<int>(s.integer("patch_size", 0, std::numeric_limits<int>::max()));
    expectHeader(s.path("patch_size"), m.patch_size, header.patch_size, "patch_size");
    m.block_cells = static_cast<int>(s.integer("block_cells", 0, std::numeric_limits<int>::max()));
    expectHeader(s.path("block_cells"), m.block_cells, header.block_cells, "block_cells");

    m.codec = s.string("codec");
    const std::optional<CodecId> id = codecIdOf(m.codec);
    if (!id)
        reject(s.path("codec") + " is \"" + m.codec + "\": not a codec (" + codecNameList() + ")");
    if (static_cast<uint32_t>(*id) != header.codec_id)
        reject(s.path("codec") + " is \"" + m.codec + "\" (codec id " +
               std::to_string(static_cast<uint32_t>(*id)) + ") but the header's codec_id is " +
               std::to_string(header.codec_id));
    m.filter = s.string("filter");
    const char* filter = filterName(static_cast<PyramidFilter>(header.filter_id));
    if (m.filter != filter)
        reject(s.path("filter") + " is \"" + m.filter + "\" but the header's filter_id " +
               std::to_string(header.filter_id) + " is \"" + filter + "\"");

    m.z_scale = s.number("z_scale");
    if (m.z_scale == 0)
        reject(s.path("z_scale") + " is 0: must be a finite number other than 0");
    m.z_offset = s.number("z_offset");
    m.max_error = s.optionalNumber("max_error", ValueRange::nonNegative());
    m.codec_max_error = s.optionalNumber("codec_max_error", ValueRange::nonNegative());
    m.codec_variant = s.optionalString("codec_variant");
    m.block_errors = s.optionalString("block_errors");
    if (s.find("vertical_shift")) {
        const Section shift = s.section("vertical_shift");
        VerticalShiftMetadata v;
        v.from = shift.string("from");
        if (v.from.empty())
            reject(shift.path("from") + " is \"\": must name the source's vertical CRS");
        v.from_epsg =
            static_cast<int>(shift.integer("from_epsg", 1, std::numeric_limits<int>::max()));
        v.operation = shift.string("operation");
        m.vertical_shift = v;
    }
    return m;
}

WaterMetadata parseWater(const Section& s, const Header& header)
{
    WaterMetadata m;
    const json& level = s.require("sea_level");
    if (level.is_null())
        m.sea_level.reset();
    else
        m.sea_level =
            Section::numberValue(s.path("sea_level"), level,
                                 ValueRange::closed(-kMaxAbsHeightMetres, kMaxAbsHeightMetres));
    m.layer = s.optionalString("layer");
    m.samples = s.integer("samples", 0, int64_t{header.width} * int64_t{header.height});
    return m;
}

// "an array", "a string" ...: what a document that is not an object is.
const char* kindOf(const json& value)
{
    switch (value.type()) {
    case json::value_t::array:
        return "an array";
    case json::value_t::string:
        return "a string";
    case json::value_t::boolean:
        return "a boolean";
    case json::value_t::null:
        return "null";
    default:
        return "a number";
    }
}

// The parsed document, refused before anything else reads it: no NUL byte (the parser would
// take one as the end of the text and accept whatever follows), at most kMaxMetadataDepth
// levels of nesting (refused while parsing, so no deep value is ever built, serialised or
// destroyed recursively).
json parseBounded(std::string_view text)
{
    if (text.size() > kMaxMetadataBytes)
        reject("document of " + std::to_string(text.size()) + " bytes: must be at most " +
               std::to_string(kMaxMetadataBytes));
    if (const size_t nul = text.find('\0'); nul != std::string_view::npos)
        reject("not JSON: a NUL byte at offset " + std::to_string(nul) + " of " +
               std::to_string(text.size()) + " (JSON text holds none: bytes after the document?)");
    struct TooDeep {};
    const json::parser_callback_t limit_depth = [](int depth, json::parse_event_t event, json&) {
        // `depth` counts the containers around the element; the document itself is 0.
        if ((event == json::parse_event_t::object_start ||
             event == json::parse_event_t::array_start) &&
            depth >= kMaxMetadataDepth)
            throw TooDeep{};
        return true;
    };
    try {
        return json::parse(text, limit_depth);
    } catch (const TooDeep&) {
        reject("values nested more than " + std::to_string(kMaxMetadataDepth) +
               " deep: must be at most " + std::to_string(kMaxMetadataDepth));
    } catch (const json::exception& e) {
        // Syntax errors, invalid UTF-8, and numbers beyond double (1e999: so a parsed number
        // is always finite). e.what() is "[json.exception.parse_error.101] parse error at
        // ...": keep the part after the exception tag.
        const std::string what = e.what();
        const size_t tag_end = what.find("] ");
        reject("not JSON: " + (tag_end == std::string::npos ? what : what.substr(tag_end + 2)));
    }
}

} // namespace

ArchiveMetadata parseArchiveMetadata(std::string_view text, const Header& header)
{
    const json document = parseBounded(text);
    if (!document.is_object())
        reject(std::string("not a JSON object (it is ") + kindOf(document) + ")");
    const Section root(document, "");
    ArchiveMetadata m;
    m.source = parseSource(root.section("source"), header);
    m.georeference = parseGeoreference(root.section("georeference"), header);
    m.build = parseBuild(root.section("build"), header);
    if (header.version >= kFirstVersionWithSampleFlags)
        m.water = parseWater(root.section("water"), header);
    else
        m.water.sea_level = 0.0;
    m.generator = root.string("generator");
    return m;
}

} // namespace ridge::archive
