// The registry of LOD schemes: a scheme is its module under schemes/ and one line here.
#include "terrain_scheme.h"

#include "ridge/core/error.h"

#include <string_view>

namespace ridge::render {

// Each module's registration function.
SchemeInfo tessellationScheme();
SchemeInfo chunkedScheme();
SchemeInfo bruteForceScheme();
SchemeInfo geomorphScheme();
SchemeInfo ringsScheme();
SchemeInfo clipmapsScheme();

const std::vector<SchemeInfo>& schemeRegistry()
{
    static const std::vector<SchemeInfo> registry = {
        tessellationScheme(), chunkedScheme(), bruteForceScheme(),
        geomorphScheme(),     ringsScheme(),   clipmapsScheme(),
    };
    return registry;
}

namespace {

const SchemeInfo* findScheme(std::string_view name)
{
    for (const SchemeInfo& s : schemeRegistry())
        if (name == s.name)
            return &s;
    return nullptr;
}

} // namespace

const SchemeInfo& schemeNamed(const std::string& name)
{
    if (const SchemeInfo* s = findScheme(name))
        return *s;
    throw Error("unknown LOD scheme '" + name + "': expected one of " + lodSchemeList());
}

const std::vector<SchemeOption>& lodSchemeOptions(const std::string& name)
{
    return schemeNamed(name).options;
}

SchemeOptions parseSchemeSpec(std::string_view spec, std::string_view what)
{
    const size_t comma = spec.find(',');
    const std::string name(spec.substr(0, comma));
    const SchemeInfo* info = findScheme(name);
    if (!info)
        throw Error(std::string(what) + " " + (name.empty() ? "''" : name) +
                    ": not a LOD scheme; expected one of " + lodSchemeList());
    if (comma != std::string_view::npos && comma + 1 == spec.size())
        throw Error(std::string(what) + " " + name + ": an empty option after the comma");
    return parseSchemeOptions(
        name, info->options,
        comma == std::string_view::npos ? std::string_view() : spec.substr(comma + 1), what);
}

std::vector<std::string> lodSchemeVariants()
{
    std::vector<std::string> specs;
    for (const SchemeInfo& s : schemeRegistry()) {
        specs.push_back(s.name);
        for (const SchemeOption& o : s.options) {
            std::vector<std::string> values;
            if (o.kind == SchemeOption::Kind::Choice)
                values = o.choices;
            else if (o.kind == SchemeOption::Kind::Flag)
                values = {"on", "off"};
            for (const std::string& v : values)
                if (v != o.default_value)
                    specs.push_back(std::string(s.name) + "," + o.key + "=" + v);
        }
    }
    return specs;
}

std::string defaultLodScheme()
{
    return schemeRegistry().front().name;
}

std::vector<std::string> lodSchemeNames()
{
    std::vector<std::string> names;
    for (const SchemeInfo& s : schemeRegistry())
        names.push_back(s.name);
    return names;
}

std::string lodSchemeList()
{
    std::string list;
    for (const SchemeInfo& s : schemeRegistry())
        list += (list.empty() ? "" : ", ") + std::string(s.name);
    return list;
}

std::string lodSchemeDescription(const std::string& name)
{
    return schemeNamed(name).description;
}

SchemePromises lodSchemePromises(const std::string& name)
{
    return schemeNamed(name).promises;
}

} // namespace ridge::render
