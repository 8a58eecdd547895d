// The registry of LOD schemes: a scheme is its module under schemes/ and one line here.
#include "terrain_scheme.h"

#include "ridge/core/error.h"

namespace ridge::render {

// Each module's registration function.
SchemeInfo tessellationScheme();
SchemeInfo chunkedScheme();
SchemeInfo bruteForceScheme();
SchemeInfo geomorphScheme();

const std::vector<SchemeInfo>& schemeRegistry()
{
    static const std::vector<SchemeInfo> registry = {
        tessellationScheme(),
        chunkedScheme(),
        bruteForceScheme(),
        geomorphScheme(),
    };
    return registry;
}

const SchemeInfo& schemeNamed(const std::string& name)
{
    for (const SchemeInfo& s : schemeRegistry())
        if (name == s.name)
            return s;
    throw Error("unknown LOD scheme '" + name + "': expected one of " + lodSchemeList());
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
