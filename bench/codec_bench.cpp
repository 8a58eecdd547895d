// Benchmark of progressive-codec decoding, the codec alone: every patch of an archive of the
// SRTM Everest tile (N27E086.hgt, 1201², 139 patches of 129²) decoded with HeightCodec::decode,
// top-down with each parent's codes, payloads already in memory. Throughput counts the 16-bit
// samples each patch covers (PyramidGeometry::coveredCells + 1 per axis). Variants, each run
// in the same process so that their ratios hold on a noisy machine:
//   v1            progressive-v1 (adaptive range coder)
//   v2            progressive-v2 (nested bound, rANS, least-squares corrections)
//   v3            progressive-v3 (v2 with row contexts, lanes decoded side by side)
//   v4            progressive (the default: v3 with parent-class contexts)
//   no-correct    progressive,payload=2|3|4,corrections=0
// and the entropy half alone (decodeResiduals) for v2, v3 and v4, so the reconstruction's
// share shows; and v4's GPU half run on the CPU (finishOnCpu from decodeForGpu's residuals,
// what a streamer pays for a parent it delivered to the GPU when a child needs its codes,
// where it paid a whole decode before);
// and JPEG-LS (CharLS, the anchor of `ridge codec-bench`) decoding the same finest level in
// 256² tiles at the same bound, the speed issue 31 measures v3 and v4 against; and the jpeg2000
// codec (issue 15): progressive with OpenJPEG, with HTJ2K (OpenJPH), and
// direct with OpenJPEG, all at the max-abs criterion; and the fractal codec (issue 25), bounded,
// on the CPU.
// Target (issues 14, 31): >= 150 MB/s per core with the defaults. Data directory: $RIDGE_DATA_DIR
// or
// ../shared/data; skips without the file.
#include "ridge/archive/archive_reader.h"
#include "ridge/codec/progressive_codec.h"
#include "ridge/codecbench/anchor_codec.h"
#include "ridge/io/raster_source.h"
#include "ridge/pipeline/build.h"
#include "ridge/pyramid/patch_context.h"

#include <benchmark/benchmark.h>

#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <unistd.h>

namespace {

std::string dataFile()
{
    const char* dir = std::getenv("RIDGE_DATA_DIR");
    return std::string(dir ? dir : RIDGE_SHARED_DATA_DIR) + "/N27E086.hgt";
}

// One archive's payloads and the decoded parents each patch needs.
struct Decodable {
    std::unique_ptr<ridge::archive::ArchiveReader> reader;
    std::vector<std::vector<uint8_t>> payloads; // [patch index]
    std::vector<std::vector<uint16_t>> codes;   // [patch index], decoded once
    std::vector<std::shared_ptr<const ridge::GpuPayload>> gpu_payloads; // [patch index], ditto
    uint64_t covered_bytes = 0;
};

const Decodable* archiveFor(const std::string& codec, double max_error)
{
    static std::map<std::string, std::unique_ptr<Decodable>> cache;
    const std::string key = codec + "@" + std::to_string(max_error);
    if (auto found = cache.find(key); found != cache.end())
        return found->second.get();
    if (!std::filesystem::exists(dataFile()))
        return nullptr;
    if (codec.find("htj2k") != std::string::npos)
        setenv("RIDGE_ALLOW_HTJ2K", "1", 0); // our own archive, built just below: trusted
    const std::string path =
        (std::filesystem::temp_directory_path() / ("ridge_codec_bench_" + std::to_string(getpid()) +
                                                   "_" + std::to_string(cache.size()) + ".ridge"))
            .string();
    ridge::BuildOptions options;
    options.codec = codec;
    options.max_error = max_error;
    ridge::buildArchive(dataFile(), path, options);
    auto d = std::make_unique<Decodable>();
    d->reader = std::make_unique<ridge::archive::ArchiveReader>(path);
    std::filesystem::remove(path); // the reader keeps its descriptor
    const ridge::PyramidGeometry& g = d->reader->geometry();
    const size_t samples = size_t(g.patchSize()) * g.patchSize();
    for (int64_t i = 0; i < g.patchCount(); ++i) {
        const ridge::PatchId p = g.patchAt(i);
        const std::vector<uint8_t> blob = d->reader->readBlob(p);
        d->payloads.emplace_back(blob.begin() + long(d->reader->payloadOffset(p, blob)),
                                 blob.end());
        d->codes.emplace_back(samples);
        const uint16_t* parent =
            p.level > 0 ? d->codes[size_t(g.patchIndex(p.parent()))].data() : nullptr;
        const auto ctx = ridge::patchContext(g, p, parent);
        const ridge::HeightCodec& c = d->reader->codec();
        if (c.decode(d->codes.back().data(), d->payloads.back().data(), d->payloads.back().size(),
                     ctx) != 0)
            return nullptr;
        d->gpu_payloads.emplace_back();
        if (c.capabilities().gpu.decodes(p.level) &&
            c.decodeForGpu(d->payloads.back().data(), d->payloads.back().size(), ctx,
                           &d->gpu_payloads.back()) != 0)
            return nullptr;
        d->covered_bytes += uint64_t(g.coveredCellsX(p) + 1) * uint64_t(g.coveredCellsY(p) + 1) * 2;
    }
    return cache.emplace(key, std::move(d)).first->second.get();
}

// What each patch is decoded from: its payload (decode, or below the root the entropy half
// alone) or its GPU half's payload (finishOnCpu; patches the codec does not decode on the GPU,
// the progressive root, are decoded).
enum class Half { Whole, Entropy, Reconstruction };

void decodeAll(benchmark::State& state, const std::string& codec, Half half)
{
    const Decodable* d = archiveFor(codec, double(state.range(0)));
    if (!d) {
        state.SkipWithError(("needs " + dataFile()).c_str());
        return;
    }
    const ridge::PyramidGeometry& g = d->reader->geometry();
    const auto* progressive = dynamic_cast<const ridge::ProgressiveCodec*>(&d->reader->codec());
    std::vector<uint16_t> out(size_t(g.patchSize()) * g.patchSize());
    std::vector<int32_t> residuals(out.size());
    for (auto _ : state) {
        for (int64_t i = 0; i < g.patchCount(); ++i) {
            const ridge::PatchId p = g.patchAt(i);
            const uint16_t* parent =
                p.level > 0 ? d->codes[size_t(g.patchIndex(p.parent()))].data() : nullptr;
            const auto ctx = ridge::patchContext(g, p, parent);
            const auto& payload = d->payloads[size_t(i)];
            int status;
            if (half == Half::Entropy && p.level > 0)
                status = progressive->decodeResiduals(payload.data(), payload.size(), ctx,
                                                      residuals.data());
            else if (half == Half::Reconstruction && d->gpu_payloads[size_t(i)])
                status =
                    d->reader->codec().finishOnCpu(*d->gpu_payloads[size_t(i)], ctx, out.data());
            else
                status = d->reader->codec().decode(out.data(), payload.data(), payload.size(), ctx);
            benchmark::DoNotOptimize(status);
        }
        benchmark::ClobberMemory();
    }
    state.SetBytesProcessed(int64_t(state.iterations()) * int64_t(d->covered_bytes));
    state.counters["archive_bytes"] = double(d->reader->fileSize());
}

void BM_DecodeV1(benchmark::State& s)
{
    decodeAll(s, "progressive-v1", Half::Whole);
}
void BM_DecodeV2(benchmark::State& s)
{
    decodeAll(s, "progressive-v2", Half::Whole);
}
void BM_DecodeV2NoCorrections(benchmark::State& s)
{
    decodeAll(s, "progressive,payload=2,corrections=0", Half::Whole);
}
void BM_EntropyOnlyV2(benchmark::State& s)
{
    decodeAll(s, "progressive-v2", Half::Entropy);
}
void BM_DecodeV3(benchmark::State& s)
{
    decodeAll(s, "progressive-v3", Half::Whole);
}
void BM_DecodeV3NoCorrections(benchmark::State& s)
{
    decodeAll(s, "progressive,payload=3,corrections=0", Half::Whole);
}
void BM_EntropyOnlyV3(benchmark::State& s)
{
    decodeAll(s, "progressive-v3", Half::Entropy);
}
void BM_DecodeV4(benchmark::State& s)
{
    decodeAll(s, "progressive", Half::Whole);
}
void BM_EntropyOnlyV4(benchmark::State& s)
{
    decodeAll(s, "progressive", Half::Entropy);
}
void BM_FinishOnCpuV4(benchmark::State& s)
{
    decodeAll(s, "progressive", Half::Reconstruction);
}
// The finest level in 256² tiles, coded by JPEG-LS within `max_error` codes.
struct AnchorTiles {
    std::vector<std::vector<uint8_t>> streams;
    std::vector<std::pair<int, int>> sizes;
    uint64_t bytes = 0; // of 16-bit samples
};

const AnchorTiles* jpegLsTiles(int max_error)
{
    static std::map<int, std::unique_ptr<AnchorTiles>> cache;
    if (auto found = cache.find(max_error); found != cache.end())
        return found->second.get();
    if (!std::filesystem::exists(dataFile()))
        return nullptr;
    const ridge::io::ElevationRaster raster = ridge::io::ingestRaster(dataFile());
    const ridge::CodeGrid& grid = raster.grid;
    const auto anchor = ridge::codecbench::makeJpegLsAnchor();
    auto tiles = std::make_unique<AnchorTiles>();
    constexpr int kTile = 256;
    std::vector<uint16_t> tile;
    for (int y0 = 0; y0 < grid.height; y0 += kTile)
        for (int x0 = 0; x0 < grid.width; x0 += kTile) {
            const int w = std::min(kTile, grid.width - x0), h = std::min(kTile, grid.height - y0);
            tile.resize(size_t(w) * h);
            for (int y = 0; y < h; ++y)
                std::copy_n(grid.codes.data() + size_t(y0 + y) * grid.width + x0, w,
                            tile.data() + size_t(y) * w);
            tiles->streams.push_back(anchor->encode(tile.data(), w, h, max_error));
            tiles->sizes.emplace_back(w, h);
            tiles->bytes += uint64_t(w) * h * 2;
        }
    return cache.emplace(max_error, std::move(tiles)).first->second.get();
}

void BM_DecodeJpegLs(benchmark::State& state)
{
    const AnchorTiles* tiles = jpegLsTiles(int(state.range(0)));
    if (!tiles) {
        state.SkipWithError(("needs " + dataFile()).c_str());
        return;
    }
    const auto anchor = ridge::codecbench::makeJpegLsAnchor();
    std::vector<uint16_t> out(256 * 256);
    for (auto _ : state) {
        for (size_t i = 0; i < tiles->streams.size(); ++i)
            anchor->decode(tiles->streams[i].data(), tiles->streams[i].size(),
                           tiles->sizes[i].first, tiles->sizes[i].second, int(state.range(0)),
                           out.data());
        benchmark::ClobberMemory();
    }
    state.SetBytesProcessed(int64_t(state.iterations()) * int64_t(tiles->bytes));
}

void BM_DecodeJpeg2000(benchmark::State& s)
{
    decodeAll(s, "jpeg2000", Half::Whole);
}
void BM_FinishOnCpuJpeg2000(benchmark::State& s)
{
    decodeAll(s, "jpeg2000", Half::Reconstruction);
}
void BM_DecodeJpeg2000Htj2k(benchmark::State& s)
{
    decodeAll(s, "jpeg2000,library=htj2k", Half::Whole);
}
void BM_DecodeJpeg2000Direct(benchmark::State& s)
{
    decodeAll(s, "jpeg2000,encoding=direct", Half::Whole);
}

void BM_DecodeFractal(benchmark::State& s)
{
    decodeAll(s, "fractal", Half::Whole);
}

} // namespace

// Argument: the bound in metres.
BENCHMARK(BM_DecodeV1)->Arg(1)->Arg(4)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DecodeV2)->Arg(1)->Arg(4)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DecodeV2NoCorrections)->Arg(1)->Arg(4)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_EntropyOnlyV2)->Arg(1)->Arg(4)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DecodeV3)->Arg(1)->Arg(4)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DecodeV3NoCorrections)->Arg(1)->Arg(4)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_EntropyOnlyV3)->Arg(1)->Arg(4)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DecodeV4)->Arg(1)->Arg(4)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_EntropyOnlyV4)->Arg(1)->Arg(4)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FinishOnCpuV4)->Arg(1)->Arg(4)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DecodeJpegLs)->Arg(1)->Arg(4)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DecodeJpeg2000)->Arg(1)->Arg(3)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FinishOnCpuJpeg2000)->Arg(1)->Arg(3)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DecodeJpeg2000Htj2k)->Arg(1)->Arg(3)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DecodeJpeg2000Direct)->Arg(1)->Arg(3)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DecodeFractal)->Arg(1)->Arg(4)->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
