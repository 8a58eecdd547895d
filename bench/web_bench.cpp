// Web tile throughput (issue 29): tiles per second on one thread, made by ridge serve's
// TileService from a cold and a warm cache, and written by `ridge tiles` (web::writeTiles),
// beside a baseline run in the same process: what cesium-terrain-builder does per heightmap
// tile (read a 65 × 65 grid, gzip it — no mesh), whose published rate is 150 tiles/s a
// thread. The ratio says what the error-bounded TIN, its measurement and the extensions
// cost on top of reading.
//
// Data: the real SRTM tile N27E086 (Everest, 1201², 3″) from $RIDGE_DATA_DIR or
// ../shared/data, built once into a lossless archive; skipped without it.
#include "ridge/pipeline/build.h"
#include "ridge/web/gzip.h"
#include "ridge/web/tile_sampler.h"
#include "ridge/web/tile_service.h"
#include "ridge/web/tile_writer.h"

#include <benchmark/benchmark.h>

#include <cstdlib>
#include <filesystem>
#include <unistd.h>

namespace {

namespace fs = std::filesystem;
using namespace ridge;
using namespace ridge::web;

constexpr int kFirstZoom = 9, kLastZoom = 11; // N27E086's deepest zoom at 64 cells: 11

// The lossless archive of N27E086, built once; empty when the data is missing.
const std::string& archive()
{
    static const std::string path = [] {
        const char* dir = std::getenv("RIDGE_DATA_DIR");
        const std::string input = std::string(dir ? dir : RIDGE_SHARED_DATA_DIR) + "/N27E086.hgt";
        if (!fs::exists(input))
            return std::string();
        const std::string out = (fs::temp_directory_path() /
                                 ("ridge-web-bench-" + std::to_string(::getpid()) + ".ridge"))
                                    .string();
        BuildOptions options;
        options.progress = {};
        buildArchive(input, out, options);
        std::atexit([] {
            fs::remove(fs::temp_directory_path() /
                       ("ridge-web-bench-" + std::to_string(::getpid()) + ".ridge"));
        });
        return out;
    }();
    return path;
}

bool haveData(benchmark::State& state)
{
    if (archive().empty()) {
        state.SkipWithError("N27E086.hgt not found (RIDGE_DATA_DIR or ../shared/data): skipped");
        return false;
    }
    return true;
}

// Every available geographic tile of zooms kFirstZoom..kLastZoom over the archive.
std::vector<TileKey> meshTiles(Tileset& set)
{
    std::vector<TileKey> keys;
    for (int z = kFirstZoom; z <= kLastZoom; ++z)
        for (const TileRange& r : set.available(z))
            for (int64_t y = r.y0; y <= r.y1; ++y)
                for (int64_t x = r.x0; x <= r.x1; ++x)
                    keys.push_back({z, x, y});
    return keys;
}

WebRequest terrainRequest(const std::string& set, TileKey k)
{
    WebRequest r;
    r.path = "/" + set + "/" + std::to_string(k.z) + "/" + std::to_string(k.x) + "/" +
             std::to_string(k.y) + ".terrain";
    r.accept = "application/vnd.quantized-mesh;extensions=octvertexnormals-watermask-metadata";
    r.accept_encoding = "gzip";
    return r;
}

TileServiceOptions oneThread()
{
    TileServiceOptions o;
    o.tileset.samplers = 1;
    return o;
}

// The baseline: a 65 × 65 grid read from the archive level the tile needs, gzip-compressed
// as heightmap-1.0 tiles are (what cesium-terrain-builder makes per tile). Cold caches.
void BM_HeightmapBaseline(benchmark::State& state)
{
    if (!haveData(state))
        return;
    int64_t tiles = 0;
    for (auto _ : state) {
        TileSampler sampler(archive());
        Tileset set("n27e086", archive(), oneThread().tileset);
        for (const TileKey& k : meshTiles(set)) {
            const std::optional<SampledTile> t = sampler.sample(k, 64);
            if (!t)
                continue;
            std::vector<int16_t> heights(t->grid.heights.size());
            for (size_t i = 0; i < heights.size(); ++i)
                heights[i] = int16_t(std::lround((t->grid.heights[i] + 1000.0f) * 5.0f));
            benchmark::DoNotOptimize(detail::gzipCompress(std::string_view(
                reinterpret_cast<const char*>(heights.data()), heights.size() * 2)));
            ++tiles;
        }
    }
    state.counters["tiles/s"] = benchmark::Counter(double(tiles), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_HeightmapBaseline)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);

// quantized-mesh tiles through TileService::handle with empty tile and patch caches: what a
// freshly started `ridge serve` costs per tile, on one sampler.
void BM_QuantizedMeshCold(benchmark::State& state)
{
    if (!haveData(state))
        return;
    int64_t tiles = 0;
    for (auto _ : state) {
        TileService service({archive()}, oneThread());
        const std::string name = service.tilesets()[0]->name();
        for (const TileKey& k : meshTiles(*service.tilesets()[0]))
            if (service.handle(terrainRequest(name, k)).status == 200)
                ++tiles;
    }
    state.counters["tiles/s"] = benchmark::Counter(double(tiles), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_QuantizedMeshCold)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);

// The same requests answered from the tile cache (every tile made once before).
void BM_QuantizedMeshWarm(benchmark::State& state)
{
    if (!haveData(state))
        return;
    TileService service({archive()}, oneThread());
    const std::string name = service.tilesets()[0]->name();
    const std::vector<TileKey> keys = meshTiles(*service.tilesets()[0]);
    for (const TileKey& k : keys)
        service.handle(terrainRequest(name, k));
    int64_t tiles = 0;
    for (auto _ : state)
        for (const TileKey& k : keys)
            if (service.handle(terrainRequest(name, k)).status == 200)
                ++tiles;
    state.counters["tiles/s"] = benchmark::Counter(double(tiles), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_QuantizedMeshWarm)->Unit(benchmark::kMillisecond)->UseRealTime();

// `ridge tiles` on one thread: every quantized-mesh (arg 0) or terrain-RGB PNG (arg 1) tile
// of zooms 0..11 (0..10 for 256-px terrain-RGB) into a PMTiles file.
void BM_TilesWrite(benchmark::State& state)
{
    if (!haveData(state))
        return;
    const fs::path out =
        fs::temp_directory_path() / ("ridge-web-bench-" + std::to_string(::getpid()) + ".pmtiles");
    TileWriteOptions options;
    options.threads = 1;
    options.format = state.range(0) == 0 ? TileFormat::QuantizedMesh : TileFormat::MapboxRgb;
    int64_t tiles = 0;
    for (auto _ : state) {
        fs::remove(out);
        tiles += int64_t(writeTiles(archive(), out.string(), options).tiles);
    }
    fs::remove(out);
    state.counters["tiles/s"] = benchmark::Counter(double(tiles), benchmark::Counter::kIsRate);
    state.SetLabel(tileFormatName(options.format));
}
BENCHMARK(BM_TilesWrite)
    ->Arg(0)
    ->Arg(1)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(3);

} // namespace

BENCHMARK_MAIN();
