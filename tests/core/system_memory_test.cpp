#include "ridge/core/system_memory.h"

#include "test_support.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace ridge {
namespace {

void writeFile(const std::filesystem::path& path, const std::string& text)
{
    std::filesystem::create_directories(path.parent_path());
    std::ofstream(path) << text;
}

// A fake /proc and /sys/fs/cgroup under `dir`, without rlimits (those are the process's own).
SystemMemoryPaths fakePaths(const test::ScratchDir& dir)
{
    SystemMemoryPaths p;
    p.meminfo = dir.path("meminfo");
    p.self_cgroup = dir.path("cgroup");
    p.self_status = dir.path("status");
    p.cgroup_root = dir.path("sys");
    p.read_rlimits = false;
    return p;
}

TEST(SystemMemory, MemAvailableIsTheAnswerWithoutOtherLimits)
{
    test::ScratchDir dir;
    writeFile(dir.path("meminfo"),
              "MemTotal:  4000 kB\nMemFree:  100 kB\nMemAvailable:  2000 kB\n");
    const AvailableMemory m = availableMemory(fakePaths(dir));
    EXPECT_EQ(m.bytes, 2000u * 1024);
    EXPECT_EQ(m.source, "MemAvailable");
}

TEST(SystemMemory, ACgroupV2LimitOfAnAncestorBindsWhenItIsTighter)
{
    test::ScratchDir dir;
    writeFile(dir.path("meminfo"), "MemAvailable:  2000 kB\n");
    writeFile(dir.path("cgroup"), "0::/a/b\n");
    writeFile(dir.path("sys/a/b/memory.max"), "max\n");
    writeFile(dir.path("sys/a/b/memory.current"), "4096\n");
    writeFile(dir.path("sys/a/memory.max"), "1000000\n");
    writeFile(dir.path("sys/a/memory.current"), "400000\n");
    const AvailableMemory m = availableMemory(fakePaths(dir));
    EXPECT_EQ(m.bytes, 600000u);
    EXPECT_EQ(m.source, "cgroup memory.max");
}

TEST(SystemMemory, ACgroupV1LimitCountsAndItsNoLimitValueDoesNot)
{
    test::ScratchDir dir;
    writeFile(dir.path("meminfo"), "MemAvailable:  2000 kB\n");
    writeFile(dir.path("cgroup"), "5:cpu:/\n4:memory:/x\n0::/\n");
    writeFile(dir.path("sys/memory/x/memory.limit_in_bytes"), "500000\n");
    writeFile(dir.path("sys/memory/x/memory.usage_in_bytes"), "100000\n");
    writeFile(dir.path("sys/memory/memory.limit_in_bytes"), "9223372036854771712\n");
    writeFile(dir.path("sys/memory/memory.usage_in_bytes"), "100000\n");
    AvailableMemory m = availableMemory(fakePaths(dir));
    EXPECT_EQ(m.bytes, 400000u);
    EXPECT_EQ(m.source, "cgroup memory.limit_in_bytes");

    std::filesystem::remove(dir.path("sys/memory/x/memory.limit_in_bytes"));
    m = availableMemory(fakePaths(dir));
    EXPECT_EQ(m.source, "MemAvailable") << "v1's 'no limit' (2^63 - 4096) is no limit";
}

TEST(SystemMemory, UsageAboveTheLimitLeavesNothingRatherThanWrappingAround)
{
    test::ScratchDir dir;
    writeFile(dir.path("cgroup"), "0::/\n");
    writeFile(dir.path("sys/memory.max"), "1000\n");
    writeFile(dir.path("sys/memory.current"), "5000\n");
    EXPECT_EQ(availableMemory(fakePaths(dir)).bytes, 0u);
}

TEST(SystemMemory, NoReadableLimitMeansUnknown)
{
    test::ScratchDir dir;
    const AvailableMemory m = availableMemory(fakePaths(dir));
    EXPECT_FALSE(m.known());
}

TEST(SystemMemory, ThisProcessHasSomeMemoryAvailable)
{
    const AvailableMemory m = availableMemory();
    ASSERT_TRUE(m.known()) << "Linux has /proc/meminfo";
    EXPECT_GT(m.bytes, 0u);
    EXPECT_FALSE(m.source.empty());
}

TEST(SystemMemory, BytesAreFormattedWithThreeSignificantDigits)
{
    EXPECT_EQ(formatBytes(512), "512 B");
    EXPECT_EQ(formatBytes(3 * 1024 * 1024 + 400 * 1024), "3.39 MiB");
    EXPECT_EQ(formatBytes(uint64_t(21.3 * 1073741824.0)), "21.3 GiB");
    EXPECT_EQ(formatBytes(uint64_t(477) << 30), "477 GiB");
    EXPECT_EQ(formatBytes(UINT64_MAX), "16.0 EiB");
}

} // namespace
} // namespace ridge
