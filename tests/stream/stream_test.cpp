#include "fixture_archives.h"

#include "ridge/codec/progressive_codec.h"
#include "ridge/core/error.h"
#include "ridge/lod/chunk_mesh.h"
#include "ridge/pipeline/build.h"
#include "ridge/pipeline/level_decoder.h"
#include "ridge/stream/patch_loader.h"
#include "ridge/stream/patch_streamer.h"
#include "ridge/stream/refinement.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <thread>

using namespace ridge;

namespace {

std::string buildFixture(const test::ScratchDir& dir, const std::string& codec)
{
    return test::buildEverestArchive(dir, codec);
}

} // namespace

TEST(PatchLoader, DecodesWhatTheLevelDecoderDecodesAndCachesIt)
{
    test::ScratchDir dir;
    for (const char* codec : {"lossless", "progressive"}) {
        const archive::ArchiveReader reader(buildFixture(dir, codec));
        stream::PatchLoader loader(reader, 64);
        const int finest = reader.geometry().finestLevel();
        const DecodedPatches level = decodePatches(reader, finest, 2, 1, 2, 1);
        const int n = reader.geometry().patchSize();
        std::vector<uint16_t> expected(size_t(n) * n);
        level.copyPatch({finest, 2, 1}, n, expected.data());

        const auto patch = loader.load({finest, 2, 1});
        EXPECT_EQ(patch->codes, expected) << codec;
        EXPECT_EQ(patch->block_errors.size(), size_t(reader.blockLayout().valuesPerPatch()));
        const uint64_t decoded = loader.stats().decoded;
        // The progressive codec needs the ancestors: decoded first, once.
        EXPECT_EQ(decoded, std::string(codec) == "progressive" ? uint64_t(finest + 1) : 1u)
            << codec;
        EXPECT_EQ(loader.load({finest, 2, 1}).get(), patch.get())
            << "a cached patch is not decoded again";
        EXPECT_EQ(loader.stats().decoded, decoded);
        EXPECT_GE(loader.stats().cache_hits, 1u);
        EXPECT_GT(loader.stats().bytes_read, 0u);
    }
}

TEST(PatchLoader, EvictsTheLeastRecentlyUsedAndNamesACorruptPatch)
{
    test::ScratchDir dir;
    const std::string path = buildFixture(dir, "lossless");
    {
        const archive::ArchiveReader reader(path);
        stream::PatchLoader loader(reader, 6); // at least the depth + 1 (5 levels here)
        const int L = reader.geometry().finestLevel();
        for (int x = 0; x < 8; ++x)
            loader.load({L, x, 0});
        const uint64_t decoded = loader.stats().decoded;
        loader.load({L, 7, 0}); // still cached
        EXPECT_EQ(loader.stats().decoded, decoded);
        loader.load({L, 0, 0}); // evicted by the later ones
        EXPECT_EQ(loader.stats().decoded, decoded + 1);
    }
    // Flip a byte in the first blob (a finest patch: streamed builds write those first).
    {
        std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(200);
        f.put('\x33');
    }
    const archive::ArchiveReader reader(path);
    stream::PatchLoader loader(reader);
    try {
        loader.load({reader.geometry().finestLevel(), 0, 0});
        FAIL() << "a corrupt patch must not decode";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("patch (level"), std::string::npos) << e.what();
    }
}

TEST(PatchStreamer, DeliversWhatTheLoaderDecodesWithoutBlockingTheCaller)
{
    test::ScratchDir dir;
    for (const char* codec : {"lossless", "progressive"}) {
        const archive::ArchiveReader reader(buildFixture(dir, codec));
        stream::PatchStreamer streamer(reader, stream::StreamerOptions::forRamBudget(64 << 20, 2));
        stream::PatchLoader loader(reader);
        const PyramidGeometry& g = reader.geometry();
        const int L = g.finestLevel();
        streamer.beginFrame();
        std::vector<PatchId> wanted;
        for (int x = 0; x < g.patchesX(L); ++x)
            wanted.push_back({L, x, 1});
        for (size_t k = 0; k < wanted.size(); ++k)
            streamer.request(wanted[k], double(k));
        streamer.waitIdle();
        const auto ready = streamer.takeReady();
        EXPECT_EQ(ready.size(), wanted.size()) << codec;
        for (const auto& patch : ready)
            EXPECT_EQ(patch->codes, loader.load(patch->id)->codes) << codec;
        EXPECT_TRUE(streamer.takeReady().empty()) << "each patch is delivered once";
        // Asked again: served from the RAM cache, no decoding.
        const uint64_t decoded = streamer.stats().decoded;
        streamer.request(wanted[0], 1.0);
        EXPECT_EQ(streamer.takeReady().size(), 1u);
        EXPECT_EQ(streamer.stats().decoded, decoded);
        EXPECT_GE(streamer.stats().cache_hits, 1u);
        EXPECT_TRUE(streamer.error().empty());
    }
}

TEST(PatchStreamer, DropsStaleRequestsAndServesRenewedOnes)
{
    test::ScratchDir dir;
    const archive::ArchiveReader reader(buildFixture(dir, "progressive"));
    const PyramidGeometry& g = reader.geometry();
    const int L = g.finestLevel();
    // One worker and a small RAM budget: most of the first frame's requests are still queued
    // when the next frame renews only a few of them.
    stream::PatchStreamer streamer(reader, stream::StreamerOptions::forRamBudget(1 << 20, 1));
    for (int round = 0; round < 3; ++round) {
        streamer.beginFrame();
        for (int y = 0; y < g.patchesY(L); ++y)
            for (int x = 0; x < g.patchesX(L); ++x)
                streamer.request({L, x, y}, double(x + y));
        streamer.beginFrame();
        const PatchId keep[2] = {{L, 0, 0}, {L, 3, 2}};
        for (PatchId p : keep)
            streamer.request(p, 100.0);
        streamer.waitIdle();
        std::set<int64_t> got;
        for (const auto& patch : streamer.takeReady())
            got.insert(g.patchIndex(patch->id));
        for (PatchId p : keep)
            EXPECT_TRUE(got.count(g.patchIndex(p))) << "renewed requests are served";
    }
    const stream::StreamerStats s = streamer.stats();
    EXPECT_EQ(s.queued, 0u);
    EXPECT_EQ(s.in_flight, 0u);
    EXPECT_LE(s.cache_bytes + s.compressed_bytes, size_t(1 << 20)) << "RAM caches within budget";
    EXPECT_GT(s.cancelled + s.decoded, 0u);
}

TEST(PatchStreamer, ReportsACorruptPatchOnceAndKeepsServingTheOthers)
{
    test::ScratchDir dir;
    const std::string path = buildFixture(dir, "lossless");
    {
        std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(200); // the first blob: patch (finest, 0, 0)
        f.put('\x42');
    }
    const archive::ArchiveReader reader(path);
    const int L = reader.geometry().finestLevel();
    stream::PatchStreamer streamer(reader, stream::StreamerOptions::forRamBudget(8 << 20, 2));
    streamer.beginFrame();
    streamer.request({L, 0, 0}, 1.0);
    streamer.request({L, 1, 0}, 1.0);
    streamer.waitIdle();
    const auto ready = streamer.takeReady();
    ASSERT_EQ(ready.size(), 1u);
    EXPECT_EQ(ready[0]->id, (PatchId{L, 1, 0}));
    EXPECT_NE(streamer.error().find("patch (level"), std::string::npos) << streamer.error();
    streamer.request({L, 0, 0}, 1.0); // failed patches are not retried
    streamer.waitIdle();
    EXPECT_TRUE(streamer.takeReady().empty());
}

// Payload v3's CPU half needs no parent: every patch below the root reaches the GPU as
// residuals, each decoded once. v4's reads the parent's codes, so a patch with children is
// turned into codes for them (and delivered as codes if that came first), still decoded
// once on one worker.
TEST(PatchStreamer, DeliversResidualsForTheGpuThatReconstructToTheCpuDecoding)
{
    for (const char* spec : {"progressive-v3", "progressive"}) {
        SCOPED_TRACE(spec);
        test::ScratchDir dir;
        const archive::ArchiveReader reader(buildFixture(dir, spec));
        const auto* codec = dynamic_cast<const ProgressiveCodec*>(&reader.codec());
        ASSERT_NE(codec, nullptr);
        const bool reads_parent = codec->capabilities().gpu.cpu_half_reads_parent;
        EXPECT_EQ(reads_parent, codec->variant().format == 4);
        // v4 on one worker: two workers may both decode a shared ancestor (the streamer
        // allows it, the cache keeps one), which would blur the count checked below.
        stream::StreamerOptions options =
            stream::StreamerOptions::forRamBudget(64 << 20, reads_parent ? 1 : 2);
        options.gpu_decode = true;
        stream::PatchStreamer streamer(reader, options);
        stream::PatchLoader loader(reader);
        const PyramidGeometry& g = reader.geometry();
        streamer.beginFrame();
        for (int64_t i = 0; i < g.patchCount(); ++i)
            streamer.request(g.patchAt(i), 0.0);
        streamer.waitIdle();
        const auto ready = streamer.takeReady();
        ASSERT_EQ(ready.size(), size_t(g.patchCount()));
        const int n = g.patchSize();
        std::vector<int32_t> parent_q(size_t(n) * n), q(size_t(n) * n);
        size_t narrow = 0, on_gpu = 0; // patches whose residuals are held in 16 bits
        for (const auto& patch : ready) {
            const auto expected = loader.load(patch->id);
            if (patch->id.level == 0 || (reads_parent && !patch->decodesOnGpu())) {
                EXPECT_EQ(patch->codes, expected->codes) << "decoded on the CPU";
                continue;
            }
            ASSERT_TRUE(patch->decodesOnGpu());
            ++on_gpu;
            EXPECT_TRUE(patch->block_errors.empty()) << "λ derived: the GPU derives it";
            const auto* residuals =
                dynamic_cast<const ProgressiveResiduals*>(patch->gpu_payload.get());
            ASSERT_NE(residuals, nullptr) << "the progressive codec's CPU half";
            // The CPU reconstruction of the delivered residuals gives the CPU decoder's codes.
            const PatchId p = patch->id;
            const LevelQuantizer quant = codec->quantizer(p.level);
            const auto parent = loader.load(p.parent());
            for (size_t k = 0; k < q.size(); ++k)
                parent_q[k] = quant.quantize(parent->codes[k]);
            EXPECT_NE(residuals->residuals32.empty(), residuals->residuals16.empty())
                << "one storage";
            narrow += !residuals->residuals16.empty();
            reconstructChild(residuals->wide().data(), parent_q.data(), p.childIndex(), n,
                             residuals->region, codec->variant().predictor, q.data(),
                             codec->weights(p.level));
            replicateBeyond(q.data(), n, residuals->region);
            size_t differing = 0;
            for (size_t k = 0; k < q.size(); ++k)
                differing += quant.reconstruct(q[k]) != expected->codes[k];
            EXPECT_EQ(differing, 0u) << reader.describe(p);
        }
        // Every finest patch has no child to need its codes: it reaches the GPU.
        EXPECT_GE(on_gpu, size_t(g.patchCount(g.finestLevel())));
        EXPECT_GT(narrow, on_gpu / 2);
        const stream::StreamerStats s = streamer.stats();
        const uint64_t parents = uint64_t(g.patchCount() - g.patchCount(g.finestLevel()));
        EXPECT_EQ(s.decoded, uint64_t(g.patchCount())) << "no patch is decoded twice";
        EXPECT_LE(s.finished_on_cpu, reads_parent ? parents : 0u);
        EXPECT_GT(s.bytes_read, 0u);
        EXPECT_GT(s.bytes_decoded, s.bytes_read);
    }
}

// A parent delivered to the GPU (v4's residuals, jpeg2000's difference layer), then needed as
// codes by its children's CPU halves, is finished on the CPU from its cached payload, not
// decoded again; its codes, λ and flags are what a CPU decode gives.
TEST(PatchStreamer, FinishesDeliveredPayloadsOnTheCpuForChildrenInsteadOfDecodingAgain)
{
    for (const char* spec : {"progressive", "jpeg2000"}) {
        SCOPED_TRACE(spec);
        test::ScratchDir dir;
        const archive::ArchiveReader reader(buildFixture(dir, spec));
        const GpuDecoding gpu = reader.codec().capabilities().gpu;
        ASSERT_TRUE(gpu.cpu_half_reads_parent && gpu.finishes_on_cpu);
        const PyramidGeometry& g = reader.geometry();
        const int finest = g.finestLevel();
        stream::StreamerOptions options = stream::StreamerOptions::forRamBudget(64 << 20, 1);
        options.gpu_decode = true;
        stream::PatchStreamer streamer(reader, options);
        stream::PatchLoader loader(reader);

        // Every level above the finest first, coarsest first: those the codec decodes on the
        // GPU reach it as payloads, and those with children there are then finished for them.
        streamer.beginFrame();
        for (int64_t i = 0; i < g.patchCount(); ++i)
            if (g.patchAt(i).level < finest)
                streamer.request(g.patchAt(i), double(-g.patchAt(i).level));
        streamer.waitIdle();
        const uint64_t coarse = uint64_t(g.patchCount() - g.patchCount(finest));
        uint64_t on_gpu = 0; // coarse patches the codec decodes on the GPU
        for (int level = 0; level < finest; ++level)
            on_gpu += gpu.decodes(level) ? uint64_t(g.patchCount(level)) : 0;
        size_t delivered_on_gpu = 0;
        for (const auto& patch : streamer.takeReady())
            delivered_on_gpu += patch->decodesOnGpu();
        ASSERT_EQ(delivered_on_gpu, on_gpu);
        EXPECT_EQ(streamer.stats().decoded, coarse);
        EXPECT_EQ(streamer.stats().finished_on_cpu, on_gpu - uint64_t(g.patchCount(finest - 1)));

        // Then the finest: every patch above it is needed as codes, and finished from its
        // payload.
        streamer.beginFrame();
        for (int64_t i = 0; i < g.patchCount(); ++i)
            if (g.patchAt(i).level == finest)
                streamer.request(g.patchAt(i), 0.0);
        streamer.waitIdle();
        EXPECT_EQ(streamer.takeReady().size(), size_t(g.patchCount(finest)));
        EXPECT_TRUE(streamer.error().empty()) << streamer.error();
        const stream::StreamerStats s = streamer.stats();
        EXPECT_EQ(s.decoded, uint64_t(g.patchCount())) << "no patch is decoded twice";
        EXPECT_EQ(s.finished_on_cpu, on_gpu);
        for (int64_t i = 0; i < g.patchCount(); ++i) {
            const PatchId p = g.patchAt(i);
            if (p.level == finest || !gpu.decodes(p.level))
                continue;
            const auto finished = streamer.cached(p);
            ASSERT_NE(finished, nullptr);
            ASSERT_FALSE(finished->codes.empty()) << reader.describe(p);
            const auto expected = loader.load(p);
            EXPECT_EQ(finished->codes, expected->codes) << reader.describe(p);
            EXPECT_EQ(finished->block_errors, expected->block_errors) << reader.describe(p);
            EXPECT_EQ(finished->drawable_cells, expected->drawable_cells);
            EXPECT_EQ(finished->sample_flags.flags, expected->sample_flags.flags);
        }
    }
}

TEST(PatchStreamer, DecodesFromTheCompressedCacheWithoutReadingAgain)
{
    test::ScratchDir dir;
    const archive::ArchiveReader reader(buildFixture(dir, "lossless"));
    const PyramidGeometry& g = reader.geometry();
    // Room for every blob, but for decoded patches only the minimum (a root-to-leaf chain).
    stream::StreamerOptions options;
    options.compressed_cache_bytes = size_t(64) << 20;
    options.decoded_cache_bytes = 1;
    stream::PatchStreamer streamer(reader, options);
    auto requestAll = [&] {
        streamer.beginFrame();
        for (int64_t i = 0; i < g.patchCount(); ++i)
            streamer.request(g.patchAt(i), double(i));
        streamer.waitIdle();
        return streamer.takeReady().size();
    };
    EXPECT_EQ(requestAll(), size_t(g.patchCount()));
    const stream::StreamerStats first = streamer.stats();
    uint64_t blob_bytes = 0;
    for (const archive::PatchRecord& r : reader.index())
        blob_bytes += r.size;
    EXPECT_EQ(first.bytes_read, blob_bytes) << "every blob read once";
    EXPECT_EQ(requestAll(), size_t(g.patchCount()));
    const stream::StreamerStats second = streamer.stats();
    EXPECT_EQ(second.bytes_read, first.bytes_read) << "the second pass reads nothing";
    EXPECT_GT(second.decoded, first.decoded) << "decoded patches were evicted, so decoded again";
    EXPECT_GE(second.compressed_hits - first.compressed_hits, second.decoded - first.decoded);
    EXPECT_LE(second.cache_bytes, size_t(g.levelCount() + 1) * 33 * 33 * 4 + 4096);
}

// A scheme's product as the streamer carries it: here Ulrich's chunk of the patch.
struct ChunkProduct final : stream::PatchProduct {
    lod::ChunkMesh mesh;
    std::thread::id built_on;
    size_t bytes() const override { return sizeof(*this) + mesh.indices.size() * sizeof(uint32_t); }
};

TEST(PatchStreamer, RunsTheSchemesPreparationsOnEveryDecodedPatchOnItsWorkers)
{
    test::ScratchDir dir;
    for (const char* codec : {"lossless", "progressive"}) {
        const archive::ArchiveReader reader(buildFixture(dir, codec));
        const PyramidGeometry& g = reader.geometry();
        const int n = g.patchSize();
        stream::StreamerOptions options;
        auto chunk = [&](PatchId p, const uint16_t* codes) {
            auto out = std::make_shared<ChunkProduct>();
            out->mesh = lod::buildChunkMesh(
                codes, n, 0.5 * reader.record(p).err / reader.quantization().scale,
                g.coveredCellsX(p), g.coveredCellsY(p));
            out->built_on = std::this_thread::get_id();
            return std::shared_ptr<const stream::PatchProduct>(out);
        };
        auto none = [](PatchId, const uint16_t*) {
            return std::shared_ptr<const stream::PatchProduct>();
        };
        options.preparations = {none, chunk};
        stream::PatchStreamer streamer(reader, options);
        streamer.beginFrame();
        for (int64_t i = 0; i < g.patchCount(); ++i)
            streamer.request(g.patchAt(i), double(i));
        streamer.waitIdle();
        const auto ready = streamer.takeReady();
        ASSERT_EQ(ready.size(), size_t(g.patchCount()));
        size_t simplified = 0;
        for (const auto& patch : ready) {
            ASSERT_EQ(patch->prepared.size(), 2u) << codec;
            EXPECT_FALSE(patch->prepared[0]) << "a preparation may make nothing";
            ASSERT_TRUE(patch->prepared[1]) << codec;
            const auto& product = static_cast<const ChunkProduct&>(*patch->prepared[1]);
            EXPECT_NE(product.built_on, std::this_thread::get_id()) << "on a worker";
            const lod::ChunkMesh expected = lod::buildChunkMesh(
                patch->codes.data(), n,
                0.5 * reader.record(patch->id).err / reader.quantization().scale,
                g.coveredCellsX(patch->id), g.coveredCellsY(patch->id));
            EXPECT_EQ(product.mesh.indices, expected.indices) << codec;
            EXPECT_EQ(product.mesh.surface_indices, expected.surface_indices);
            simplified += product.mesh.surface_indices < 6u * (n - 1) * (n - 1);
            EXPECT_GT(patch->bytes(), product.bytes()) << "the cache counts the product";
        }
        EXPECT_GT(simplified, ready.size() / 2) << codec;
    }
}

TEST(DecodedPatch, CountsItsGpuPayloadWhichHoldsResidualsIn16BitsWhenEveryOneFits)
{
    auto r = std::make_shared<ProgressiveResiduals>();
    r->assign({-32768, 0, 32767});
    EXPECT_EQ(r->residuals16, (std::vector<int16_t>{-32768, 0, 32767}));
    EXPECT_TRUE(r->residuals32.empty());
    EXPECT_EQ(r->wide(), (std::vector<int32_t>{-32768, 0, 32767}));
    stream::DecodedPatch p;
    p.gpu_payload = r;
    EXPECT_TRUE(p.decodesOnGpu());
    const size_t narrow_bytes = p.bytes();
    r->assign({-32768, 0, 32768});
    EXPECT_TRUE(r->residuals16.empty());
    EXPECT_EQ(r->residuals32, (std::vector<int32_t>{-32768, 0, 32768}));
    EXPECT_EQ(r->wide(), r->residuals32);
    EXPECT_EQ(p.bytes(), narrow_bytes + 3 * 2);
    EXPECT_EQ(r->uploadBytes(), 3u * 4u);
}

TEST(LruCache, EvictsTheLeastRecentlyUsedBeyondItsWeightButKeepsTheMinimumEntries)
{
    stream::LruCache<int, int> cache(100, 2);
    cache.insert(1, 10, 40);
    cache.insert(2, 20, 40);
    ASSERT_NE(cache.find(1), nullptr); // 1 is now the most recently used
    cache.insert(3, 30, 40);           // 120 > 100: the least recently used (2) goes
    EXPECT_EQ(cache.find(2), nullptr);
    EXPECT_NE(cache.find(1), nullptr);
    EXPECT_EQ(cache.weight(), 80u);
    cache.insert(4, 40, 500); // heavier than the budget: the two newest stay (minimum 2)
    EXPECT_EQ(cache.size(), 2u);
    EXPECT_NE(cache.find(4), nullptr);
    EXPECT_NE(cache.find(1), nullptr);
    EXPECT_EQ(cache.weight(), 540u);
    cache.insert(4, 41, 1); // present: kept as is
    EXPECT_EQ(*cache.find(4), 40);
    cache.assign(4, 42, 30); // replaced, with its weight
    EXPECT_EQ(*cache.find(4), 42);
    EXPECT_EQ(cache.size(), 2u);
    EXPECT_EQ(cache.weight(), 70u);
    cache.assign(5, 50, 10); // absent: inserted
    EXPECT_EQ(*cache.find(5), 50);
    EXPECT_EQ(cache.weight(), 80u);
}

namespace {

// A refinable payload with given bounds per step count (codes).
struct Steps final : RefinablePayload {
    std::vector<double> bounds;
    int fullSteps() const override { return int(bounds.size()) - 1; }
    double stepBound(int k) const override { return bounds[size_t(k)]; }
};

} // namespace

TEST(Refinement, TheFewestStepsWhoseAddedErrorKeepsThePatchWithinEpsilon)
{
    Steps s;
    s.bounds = {400, 100, 30, 12, 5, 0};
    // Err(P) = 2 m seen as 1 px: 0.5 px a metre; ε = 4 px leaves 3 px = 6 m; 1 code = 0.5 m.
    EXPECT_EQ(stream::stepsForView(s, 0.5, 2.0, 1.0, 4.0), 3);  // 12 codes = 6 m
    EXPECT_EQ(stream::stepsForView(s, 0.5, 2.0, 0.01, 4.0), 0); // far: even 400 codes fit
    EXPECT_EQ(stream::stepsForView(s, 0.5, 2.0, 3.99, 4.0), 5); // no slack: all steps
    // No view to judge by: the full decode.
    EXPECT_EQ(stream::stepsForView(s, 0.5, 0.0, 1.0, 4.0), 5);
    EXPECT_EQ(stream::stepsForView(s, 0.5, 2.0, 0.0, 4.0), 5);
    EXPECT_EQ(stream::stepsForView(s, 0.5, 2.0, std::nan(""), 4.0), 5);
    // A bound that is not monotone: the first count that fits.
    s.bounds = {400, 5, 30, 0};
    EXPECT_EQ(stream::stepsForView(s, 0.5, 2.0, 1.0, 4.0), 1);
    // No bound stored for partial decodes (infinite): all steps.
    s.bounds = {INFINITY, INFINITY, 0};
    EXPECT_EQ(stream::stepsForView(s, 0.5, 2.0, 0.01, 4.0), 2);
}
