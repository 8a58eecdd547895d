// Benchmark of `ridge build` on the 10801 x 4801 Sierra Nevada mosaic (51.9 M samples).
//
// Each iteration runs in a forked child so that the reported peak RSS is the build's own
// (ru_maxrss of a fresh process), not the benchmark harness's high-water mark. The baseline,
// run in the same process, is ingest alone (GDAL decode + conversion to codes): the ratio
// says what the pyramid, error bounds, encoding and writing cost on top of reading.
//
// Targets (issue 2, 2-core machine): >= 10 M samples/s end to end, peak RSS <= 1.5x the raw
// 16-bit input (155.6 MB). Data directory: $RIDGE_DATA_DIR or ../shared/data.
#include "ridge/io/raster_source.h"
#include "ridge/pipeline/build.h"

#include <benchmark/benchmark.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

namespace {

std::string dataFile()
{
    const char* dir = std::getenv("RIDGE_DATA_DIR");
    return std::string(dir ? dir : RIDGE_SHARED_DATA_DIR) +
           "/sierra_nevada_sfbay_10801x4801_int16.tif";
}

struct ChildRun {
    double seconds = 0.0;
    double peak_rss_mb = 0.0;
    bool ok = false;
};

// Runs `work` in a child process; returns its wall time and peak resident set.
template <typename Work> ChildRun runInChild(Work work)
{
    const auto start = std::chrono::steady_clock::now();
    const pid_t pid = fork();
    if (pid == 0) {
        try {
            work();
            std::_Exit(0);
        } catch (const std::exception& e) {
            std::fprintf(stderr, "benchmark child failed: %s\n", e.what());
            std::_Exit(1);
        }
    }
    int status = 0;
    struct rusage usage {};
    wait4(pid, &status, 0, &usage);
    ChildRun run;
    run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    run.peak_rss_mb = usage.ru_maxrss / 1024.0; // kilobytes on Linux
    run.ok = WIFEXITED(status) && WEXITSTATUS(status) == 0;
    return run;
}

template <typename Work> void measure(benchmark::State& state, Work work)
{
    const std::string input = dataFile();
    if (!std::filesystem::exists(input)) {
        state.SkipWithError(("data not found, skipped: " + input).c_str());
        return;
    }
    double peak = 0.0;
    int64_t samples = 0;
    for (auto _ : state) {
        const ChildRun run = runInChild([&] { work(input); });
        if (!run.ok) {
            state.SkipWithError("child failed");
            return;
        }
        state.SetIterationTime(run.seconds);
        peak = std::max(peak, run.peak_rss_mb);
        samples += 10801LL * 4801LL;
    }
    const double raw_mb = 10801.0 * 4801.0 * 2.0 / (1024.0 * 1024.0);
    state.counters["samples/s"] = benchmark::Counter(double(samples), benchmark::Counter::kIsRate);
    state.counters["peak_rss_MiB"] = peak;
    state.counters["peak_vs_raw16"] = peak / raw_mb;
}

void BM_IngestOnly(benchmark::State& state)
{
    measure(state, [](const std::string& input) { ridge::io::ingestRaster(input); });
}

void BM_BuildLossless(benchmark::State& state)
{
    const std::string out = std::filesystem::temp_directory_path() / "ridge-bench-build.ridge";
    measure(state, [&](const std::string& input) { ridge::buildArchive(input, out, {}); });
    std::filesystem::remove(out);
}

} // namespace

BENCHMARK(BM_IngestOnly)->UseManualTime()->Unit(benchmark::kSecond)->Iterations(3);
BENCHMARK(BM_BuildLossless)->UseManualTime()->Unit(benchmark::kSecond)->Iterations(3);
BENCHMARK_MAIN();
