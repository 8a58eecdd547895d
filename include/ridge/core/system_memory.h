#pragma once
// How much memory this process can still allocate, for operations that size themselves before
// allocating (the build refuses a raster it cannot hold instead of dying in bad_alloc).
//
// The smallest of every limit that applies (Linux):
//   MemAvailable           /proc/meminfo: what the kernel can hand out without swapping
//   cgroup memory.max      v2: memory.max − memory.current of this process's cgroup and of
//                          each ancestor; v1: memory.limit_in_bytes − memory.usage_in_bytes
//   RLIMIT_AS              the address-space limit minus the process's VmSize
//   RLIMIT_DATA            the data-segment limit minus the process's VmData
// Limits that are absent, unlimited or unreadable are skipped; with none at all the answer is
// "unknown" (bytes = UINT64_MAX), which no estimate exceeds.
#include <cstdint>
#include <string>

namespace ridge {

struct AvailableMemory {
    uint64_t bytes = UINT64_MAX; // UINT64_MAX: no limit could be determined
    std::string source;          // which limit it is: "MemAvailable", "cgroup memory.max", ...

    bool known() const { return bytes != UINT64_MAX; }
};

// Where the limits are read from; tests point these at a fake tree.
struct SystemMemoryPaths {
    std::string meminfo = "/proc/meminfo";
    std::string self_cgroup = "/proc/self/cgroup";
    std::string self_status = "/proc/self/status";
    std::string cgroup_root = "/sys/fs/cgroup"; // v2 unified hierarchy, v1 under memory/
    bool read_rlimits = true;                   // getrlimit(RLIMIT_AS, RLIMIT_DATA)
};

// The smallest limit, as described above. Never throws; costs a few small file reads.
AvailableMemory availableMemory(const SystemMemoryPaths& paths = {});

// "512 B", "3.4 MiB", "21.3 GiB", "477 GiB": three significant digits at most, binary units.
std::string formatBytes(uint64_t bytes);

} // namespace ridge
