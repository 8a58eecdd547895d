#include "ridge/core/system_memory.h"

#include <sys/resource.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>

namespace ridge {

namespace {

// cgroup v1 reports "no limit" as the largest page-aligned int64 (9223372036854771712);
// anything this large is no limit.
constexpr uint64_t kUnlimited = uint64_t{1} << 62;

std::optional<std::string> readFile(const std::string& path)
{
    std::ifstream in(path);
    if (!in)
        return std::nullopt;
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
}

// A whole file holding one number ("max" or unreadable: nullopt).
std::optional<uint64_t> readNumber(const std::string& path)
{
    const std::optional<std::string> text = readFile(path);
    if (!text)
        return std::nullopt;
    unsigned long long value = 0;
    if (std::sscanf(text->c_str(), "%llu", &value) != 1)
        return std::nullopt;
    return uint64_t{value};
}

// "Key:   1234 kB" in /proc/meminfo or /proc/self/status, in bytes.
std::optional<uint64_t> readKilobytesField(const std::string& path, const std::string& key)
{
    std::ifstream in(path);
    std::string line;
    while (std::getline(in, line)) {
        if (line.compare(0, key.size() + 1, key + ":") != 0)
            continue;
        unsigned long long kb = 0;
        if (std::sscanf(line.c_str() + key.size() + 1, "%llu", &kb) != 1)
            return std::nullopt;
        return uint64_t{kb} * 1024;
    }
    return std::nullopt;
}

struct Candidate {
    AvailableMemory best;

    void offer(uint64_t bytes, const char* source)
    {
        if (bytes < best.bytes)
            best = {bytes, source};
    }
};

uint64_t minus(uint64_t limit, uint64_t used)
{
    return limit > used ? limit - used : 0;
}

// The tightest `limit_file − usage_file` of `dir` and its ancestors up to `top` (limits of
// ancestors apply to descendants too).
void offerCgroupLimits(std::filesystem::path dir, const std::filesystem::path& top,
                       const char* limit_file, const char* usage_file, const char* source,
                       Candidate& out)
{
    for (;;) {
        const std::optional<uint64_t> limit = readNumber((dir / limit_file).string());
        const std::optional<uint64_t> usage = readNumber((dir / usage_file).string());
        if (limit && usage && *limit < kUnlimited)
            out.offer(minus(*limit, *usage), source);
        if (dir == top || !dir.has_parent_path() || dir.parent_path() == dir)
            return;
        dir = dir.parent_path();
    }
}

void offerCgroups(const SystemMemoryPaths& paths, Candidate& out)
{
    std::ifstream in(paths.self_cgroup);
    std::string line;
    const std::filesystem::path root(paths.cgroup_root);
    while (std::getline(in, line)) {
        // "hierarchy-id:controllers:path"
        const size_t a = line.find(':');
        const size_t b = a == std::string::npos ? a : line.find(':', a + 1);
        if (b == std::string::npos)
            continue;
        const std::string controllers = line.substr(a + 1, b - a - 1);
        std::string path = line.substr(b + 1);
        while (!path.empty() && path.front() == '/')
            path.erase(0, 1);
        if (line.compare(0, a, "0") == 0 && controllers.empty()) {
            offerCgroupLimits(root / path, root, "memory.max", "memory.current",
                              "cgroup memory.max", out);
        } else if (("," + controllers + ",").find(",memory,") != std::string::npos) {
            offerCgroupLimits(root / "memory" / path, root / "memory", "memory.limit_in_bytes",
                              "memory.usage_in_bytes", "cgroup memory.limit_in_bytes", out);
        }
    }
}

void offerRlimit(int resource, const SystemMemoryPaths& paths, const char* used_field,
                 const char* source, Candidate& out)
{
    rlimit limit{};
    if (getrlimit(resource, &limit) != 0 || limit.rlim_cur == RLIM_INFINITY)
        return;
    const uint64_t used = readKilobytesField(paths.self_status, used_field).value_or(0);
    out.offer(minus(uint64_t(limit.rlim_cur), used), source);
}

} // namespace

AvailableMemory availableMemory(const SystemMemoryPaths& paths)
{
    Candidate c;
    if (const std::optional<uint64_t> available = readKilobytesField(paths.meminfo, "MemAvailable"))
        c.offer(*available, "MemAvailable");
    offerCgroups(paths, c);
    if (paths.read_rlimits) {
        offerRlimit(RLIMIT_AS, paths, "VmSize", "RLIMIT_AS", c);
        offerRlimit(RLIMIT_DATA, paths, "VmData", "RLIMIT_DATA", c);
    }
    return c.best;
}

std::string formatBytes(uint64_t bytes)
{
    static const char* const kUnits[] = {"B", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
    if (bytes < 1024)
        return std::to_string(bytes) + " B";
    double value = double(bytes);
    int unit = 0;
    while (value >= 1024.0 && unit < 6) {
        value /= 1024.0;
        ++unit;
    }
    char text[32];
    // Three significant digits; 1023.6 KiB would round to "1024 KiB", which is fine.
    std::snprintf(text, sizeof text,
                  value >= 100  ? "%.0f %s"
                  : value >= 10 ? "%.1f %s"
                                : "%.2f %s",
                  value, kUnits[unit]);
    return text;
}

} // namespace ridge
