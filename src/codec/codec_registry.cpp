// The registry of patch codecs: a codec is its module under src/codec/ and one line here.
#include "ridge/codec/codec_registry.h"

#include "ridge/core/error.h"

#include <algorithm>
#include <string_view>

namespace ridge {

// Each module's registration function.
CodecInfo losslessCodec();
CodecInfo rawCodec();
CodecInfo progressiveCodec();
CodecInfo jpeg2000Codec();
CodecInfo fractalCodec();

const std::vector<CodecInfo>& codecRegistry()
{
    // One line a codec, so that adding one is a one-line diff.
    // clang-format off
    static const std::vector<CodecInfo> registry = {
        losslessCodec(),
        rawCodec(),
        progressiveCodec(),
        jpeg2000Codec(),
        fractalCodec(),
    };
    // clang-format on
    return registry;
}

const CodecInfo* findCodec(const std::string& spec)
{
    const std::string_view base = std::string_view(spec).substr(0, spec.find(','));
    for (const CodecInfo& c : codecRegistry()) {
        if (base == c.name)
            return &c;
        for (const char* alias : c.aliases)
            if (base == alias)
                return &c;
    }
    return nullptr;
}

std::string codecNameList()
{
    std::string list;
    for (const CodecInfo& c : codecRegistry()) {
        list += (list.empty() ? "" : ", ") + std::string(c.name);
        for (const char* alias : c.aliases)
            list += std::string(", ") + alias;
    }
    return list;
}

std::string codecUsage()
{
    std::string text;
    for (const CodecInfo& c : codecRegistry()) {
        text += std::string(c.name) + ": " + c.description;
        if (c.lossy)
            text += ", needs --max-error";
        if (!c.aliases.empty()) {
            text += "; also";
            for (const char* alias : c.aliases)
                text += std::string(" ") + alias;
        }
        if (*c.option_forms)
            text += std::string("; ") + c.name + "," + c.option_forms;
        text += "\n";
    }
    text.pop_back(); // the last newline
    return text;
}

std::string codecSpecProblem(const std::string& spec)
{
    const CodecInfo* c = findCodec(spec);
    if (!c)
        return "not a codec (available: " + codecNameList() + ")";
    return c->spec_problem(spec);
}

std::unique_ptr<HeightCodec> makeCodec(const std::string& spec, double max_error, int level_count)
{
    if (const std::string problem = codecSpecProblem(spec); !problem.empty())
        throw Error("codec '" + spec + "': " + problem);
    return findCodec(spec)->from_spec(spec, max_error, level_count);
}

std::optional<CodecId> codecIdOf(const std::string& spec)
{
    if (!codecSpecProblem(spec).empty())
        return std::nullopt;
    return findCodec(spec)->id;
}

bool isLossyCodec(const std::string& spec)
{
    return codecSpecProblem(spec).empty() && findCodec(spec)->lossy;
}

bool codecBuildsFinestFirst(const std::string& spec)
{
    if (!codecSpecProblem(spec).empty())
        return false;
    const CodecInfo* codec = findCodec(spec);
    return !codec->lossy || codec->finest_first;
}

std::unique_ptr<HeightCodec> makeCodec(CodecId id, const CodecSettings& settings,
                                       std::string* problem)
{
    for (const CodecInfo& c : codecRegistry())
        if (c.id == id)
            return c.from_settings(settings, problem);
    if (problem) {
        // "must be 0 (raw), 1 (lossless), 2 (progressive) or 3 (jpeg2000)", by id.
        std::vector<const CodecInfo*> by_id;
        for (const CodecInfo& c : codecRegistry())
            by_id.push_back(&c);
        std::sort(by_id.begin(), by_id.end(), [](const CodecInfo* a, const CodecInfo* b) {
            return uint32_t(a->id) < uint32_t(b->id);
        });
        std::string known;
        for (size_t k = 0; k < by_id.size(); ++k)
            known += (k == 0                  ? ""
                      : k + 1 == by_id.size() ? " or "
                                              : ", ") +
                     std::to_string(uint32_t(by_id[k]->id)) + " (" + by_id[k]->name + ")";
        *problem = "codec_id is " + std::to_string(uint32_t(id)) + ": must be " + known;
    }
    return nullptr;
}

bool forEachSpecOption(const std::string& spec, std::string_view base,
                       const std::function<bool(const std::string&, const std::string&)>& option)
{
    if (spec.rfind(base, 0) != 0)
        return false;
    if (spec.size() == base.size())
        return true;
    if (spec[base.size()] != ',')
        return false;
    size_t at = base.size() + 1;
    while (at <= spec.size()) {
        const size_t comma = std::min(spec.find(',', at), spec.size());
        const std::string item = spec.substr(at, comma - at);
        const size_t eq = item.find('=');
        if (eq == std::string::npos || !option(item.substr(0, eq), item.substr(eq + 1)))
            return false;
        at = comma + 1;
    }
    return true;
}

std::optional<int> specNumber(const std::string& value, int lo, int hi)
{
    // At most 9 digits: std::stoi never overflows.
    if (value.empty() || value.size() > 9 ||
        value.find_first_not_of("0123456789") != std::string::npos)
        return std::nullopt;
    const int number = std::stoi(value);
    if (number < lo || number > hi)
        return std::nullopt;
    return number;
}

} // namespace ridge
