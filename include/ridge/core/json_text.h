#pragma once
// JSON text of a document whose strings may hold any bytes. Paths, stdin lines and messages
// that quote them are byte strings on POSIX, not UTF-8; nlohmann's dump() throws
// type_error.316 on the first invalid UTF-8 byte, which lost a whole `--json` document (and
// made a raster with such a name impossible to build). Every JSON that ridge emits goes
// through here: invalid bytes become U+FFFD, the rest is unchanged.
#include <nlohmann/json.hpp>

#include <string>

namespace ridge {

// `indent` as nlohmann's dump: -1 compact, else spaces per level.
inline std::string jsonText(const nlohmann::json& document, int indent = 2)
{
    return document.dump(indent, ' ', false, nlohmann::json::error_handler_t::replace);
}

} // namespace ridge
