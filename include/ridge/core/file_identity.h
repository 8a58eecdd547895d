#pragma once
// Which file a path names, so that no output replaces one of its inputs whatever path reaches
// it: "./x", "dir/../x", a symlink, a hard link and a bind mount all name the same (st_dev,
// st_ino). Comparing path strings would miss every one of those.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace ridge {

struct FileIdentity {
    uint64_t device = 0; // st_dev of the file (not of a symlink naming it)
    uint64_t inode = 0;  // st_ino
    friend bool operator==(const FileIdentity&, const FileIdentity&) = default;
};

// The identity of the file `path` names, symlinks followed (stat(2)). nullopt when nothing can
// be reached there: a missing file (an output about to be created), a dangling symlink, a
// GDAL virtual path ("/vsizip/..."), a directory that cannot be searched. Never throws.
std::optional<FileIdentity> fileIdentity(const std::string& path);

// Throws Error("OUTPUT: is the same file as the input INPUT; refusing to replace an input")
// when `output` names the same file as any of `inputs`. Operations call it first, before any
// work, so that the input is never touched. Paths without an identity (see fileIdentity)
// never match. Costs one stat per path.
void refuseOutputOverInput(const std::string& output, const std::vector<std::string>& inputs);

} // namespace ridge
