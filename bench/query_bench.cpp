// Height queries through the public API (<ridge/ridge.h>, libridge), Google Benchmark:
// Terrain::heights over a span of points against the one-point Terrain::height loop in the
// same process (the baseline), on SRTM tile N27E086 (1201², lossless and progressive 1 m),
// and longitude/latitude through PROJ on a projected archive.
//
//   ./build/bench/ridge_bench_query     # data: $RIDGE_DATA_DIR or ../shared/data
//
// "Warm": the decoded-patch cache holds every patch the points touch (the default 256 holds
// the tile's 100 finest patches and their ancestors), so the figures are the query's own
// cost. The "cache 16" rows keep a cache smaller than what random points touch: point by
// point nearly every point decodes its patch again, a batch decodes each patch once.
#include <ridge/ridge.h>

#include <benchmark/benchmark.h>

#include <cstdlib>
#include <filesystem>
#include <memory>
#include <random>
#include <string>
#include <vector>

namespace {

constexpr int64_t kPoints = 1 << 20;

struct Fixture {
    std::string error;
    std::string lossless, progressive;
    std::vector<std::array<double, 2>> local, crs, lonlat;
};

const Fixture& fixture()
{
    static const Fixture f = [] {
        Fixture out;
        const char* dir = std::getenv("RIDGE_DATA_DIR");
        const std::string input = std::string(dir ? dir : RIDGE_SHARED_DATA_DIR) + "/N27E086.hgt";
        if (!std::filesystem::exists(input)) {
            out.error = "data not found, skipped: " + input;
            return out;
        }
        const auto tmp = std::filesystem::temp_directory_path();
        out.lossless = (tmp / "ridge_bench_query_lossless.ridge").string();
        out.progressive = (tmp / "ridge_bench_query_progressive.ridge").string();
        if (!std::filesystem::exists(out.lossless))
            ridge::build(input, out.lossless);
        if (!std::filesystem::exists(out.progressive)) {
            ridge::BuildParameters p;
            p.codec = "progressive";
            p.max_error = 1.0;
            ridge::build(input, out.progressive, p);
        }
        // Uniform random points over the tile, in local metres, in its CRS (lon/lat degrees
        // here) and through PROJ.
        const ridge::Terrain terrain(out.lossless);
        const ridge::TerrainInfo& info = terrain.info();
        const auto& gt = *info.geotransform;
        std::mt19937_64 rng(1);
        std::uniform_real_distribution<double> u(0.0, 1.0);
        for (int64_t k = 0; k < kPoints; ++k) {
            const double pixel = u(rng) * double(info.width), line = u(rng) * double(info.height);
            const ridge::LocalPoint p = terrain.localFromPixel(pixel, line);
            out.local.push_back({p.x, p.y});
            out.crs.push_back(
                {gt[0] + pixel * gt[1] + line * gt[2], gt[3] + pixel * gt[4] + line * gt[5]});
        }
        out.lonlat = out.crs; // a geographic WGS 84 tile: the CRS is longitude/latitude
        return out;
    }();
    return f;
}

const std::vector<std::array<double, 2>>& pointsIn(ridge::Coordinates c)
{
    return c == ridge::Coordinates::Local ? fixture().local
           : c == ridge::Coordinates::Crs ? fixture().crs
                                          : fixture().lonlat;
}

// The baseline: one Terrain::height call a point (bilinear, local coordinates).
void BM_HeightLoop(benchmark::State& state)
{
    if (!fixture().error.empty())
        return state.SkipWithError(fixture().error.c_str());
    const ridge::Terrain terrain(state.range(1) ? fixture().progressive : fixture().lossless,
                                 size_t(state.range(2)));
    const auto& points = fixture().local;
    const int64_t n = state.range(0);
    for (int64_t k = 0; k < n; ++k) // warm: every patch decoded once
        benchmark::DoNotOptimize(terrain.height(points[size_t(k)][0], points[size_t(k)][1]));
    for (auto _ : state)
        for (int64_t k = 0; k < n; ++k)
            benchmark::DoNotOptimize(terrain.height(points[size_t(k)][0], points[size_t(k)][1]));
    state.SetItemsProcessed(state.iterations() * n);
}

// Terrain::heights over the first range(0) points: coordinates range(3), resampling range(4).
void BM_HeightsBatch(benchmark::State& state)
{
    if (!fixture().error.empty())
        return state.SkipWithError(fixture().error.c_str());
    const ridge::Terrain terrain(state.range(1) ? fixture().progressive : fixture().lossless,
                                 size_t(state.range(2)));
    ridge::QueryParameters q;
    q.coordinates = ridge::Coordinates(state.range(3));
    q.resampling = ridge::Resampling(state.range(4));
    const std::span<const std::array<double, 2>> points(pointsIn(q.coordinates).data(),
                                                        size_t(state.range(0)));
    std::vector<ridge::PointHeight> out(points.size());
    terrain.heights(points, out, q); // warm
    for (auto _ : state) {
        terrain.heights(points, out, q);
        benchmark::DoNotOptimize(out.data());
    }
    state.SetItemsProcessed(state.iterations() * int64_t(points.size()));
}

// Longitude/latitude over a projected archive (the UTM 45N test fixture): PROJ's transform
// a point, against local coordinates on the same archive.
void BM_HeightsProjected(benchmark::State& state)
{
    static const std::string archive = [] {
        const std::string path =
            (std::filesystem::temp_directory_path() / "ridge_bench_query_utm45.ridge").string();
        if (!std::filesystem::exists(path))
            ridge::build(std::string(RIDGE_TEST_DATA_DIR) + "/everest_utm45.tif", path);
        return path;
    }();
    const ridge::Terrain terrain(archive);
    const ridge::TerrainInfo& info = terrain.info();
    std::mt19937_64 rng(2);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<std::array<double, 2>> points;
    ridge::QueryParameters q;
    q.coordinates = ridge::Coordinates(state.range(0));
    for (int k = 0; k < (1 << 18); ++k) {
        const ridge::LocalPoint p =
            terrain.localFromPixel(u(rng) * double(info.width), u(rng) * double(info.height));
        points.push_back(q.coordinates == ridge::Coordinates::LonLat
                             ? terrain.lonLatFromLocal(p.x, p.y)
                             : std::array<double, 2>{p.x, p.y});
    }
    std::vector<ridge::PointHeight> out(points.size());
    terrain.heights(points, out, q); // warm
    for (auto _ : state) {
        terrain.heights(points, out, q);
        benchmark::DoNotOptimize(out.data());
    }
    state.SetItemsProcessed(state.iterations() * int64_t(points.size()));
}

constexpr int64_t kLocal = int64_t(ridge::Coordinates::Local);
constexpr int64_t kCrs = int64_t(ridge::Coordinates::Crs);
constexpr int64_t kLonLat = int64_t(ridge::Coordinates::LonLat);
constexpr int64_t kBilinear = int64_t(ridge::Resampling::Bilinear);
constexpr int64_t kNearest = int64_t(ridge::Resampling::Nearest);

// Args: points, progressive?, cache patches[, coordinates, resampling].
BENCHMARK(BM_HeightLoop)
    ->ArgNames({"points", "progressive", "cache"})
    ->Args({kPoints, 0, 256})
    ->Args({kPoints, 1, 256})
    ->Args({1 << 12, 1, 16}) // a millisecond a point: fewer of them
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_HeightsBatch)
    ->ArgNames({"points", "progressive", "cache", "coordinates", "resampling"})
    ->Args({kPoints, 0, 256, kLocal, kBilinear})
    ->Args({kPoints, 0, 256, kLocal, kNearest})
    ->Args({kPoints, 0, 256, kCrs, kNearest})
    ->Args({kPoints, 0, 256, kLonLat, kNearest})
    ->Args({kPoints, 1, 256, kLocal, kBilinear})
    ->Args({1 << 16, 1, 16, kLocal, kBilinear})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_HeightsProjected)
    ->ArgNames({"coordinates"})
    ->Arg(kLocal)
    ->Arg(kLonLat)
    ->Unit(benchmark::kMillisecond);

} // namespace

BENCHMARK_MAIN();
