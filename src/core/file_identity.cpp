#include "ridge/core/file_identity.h"

#include "ridge/core/error.h"

#include <sys/stat.h>

namespace ridge {

std::optional<FileIdentity> fileIdentity(const std::string& path)
{
    struct stat st {};
    if (path.empty() || ::stat(path.c_str(), &st) != 0)
        return std::nullopt;
    return FileIdentity{static_cast<uint64_t>(st.st_dev), static_cast<uint64_t>(st.st_ino)};
}

void refuseOutputOverInput(const std::string& output, const std::vector<std::string>& inputs)
{
    const std::optional<FileIdentity> out = fileIdentity(output);
    if (!out)
        return;
    for (const std::string& input : inputs)
        if (fileIdentity(input) == out)
            throw Error(output + ": is the same file as the input " + input +
                        "; refusing to replace an input (choose another output path)");
}

} // namespace ridge
