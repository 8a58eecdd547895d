// Streaming: draw() never waits, never shows a hole, stays within its budgets, and converges
// to full detail once the workers are done.
#include "captured_surface_checks.h"
#include "fixture_archives.h"
#include "patch_textures.h"
#include "resident_set.h"
#include "streaming_checks.h"

#include "ridge/gpu/context.h"
#include "ridge/gpu/render_target.h"
#include "ridge/pipeline/build.h"
#include "ridge/render/terrain_renderer.h"
#include "ridge/stream/patch_loader.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <tuple>

using namespace ridge;

using test::flyover;
using test::holesOrOverlaps;
using test::StreamingScene;

TEST(Streaming, AFastFlyOverUnderATinyBudgetNeverShowsAHoleAndStaysWithinBudget)
{
    // Codes uploaded (lossless), and every codec decoded on the GPU.
    std::vector<std::string> codecs = test::gpuDecodedCodecs();
    codecs.insert(codecs.begin(), "lossless");
    for (const std::string& codec_name : codecs)
        for (const int prefetch : {0, 20}) {
            const char* codec = codec_name.c_str();
            StreamingScene scene(codec);
            render::RendererOptions options;
            options.prefetch_frames = prefetch;
            options.streaming = true;
            // 24 slots of 33² patches (and of the GPU decoder's state).
            const render::SchemePlan plan = render::planSchemes(
                *scene.reader,
                lod::terrainFrameOf(*scene.reader, options.frame, scene.reader->path()), options);
            options.vram_budget_mb =
                24 *
                render::PatchTextures::bytesPerSlot(
                    33, scene.reader->blockLayout(), false,
                    render::ResidentSet::gpuDecodedCodec(*scene.reader, options, plan)) /
                (1024 * 1024);
            options.ram_budget_mb = 0.25;
            options.uploads_per_frame = 3;
            render::TerrainRenderer renderer(*scene.reader, options);
            ASSERT_EQ(renderer.residentSlots(), 24);
            gpu::RenderTarget target(320, 180, 1);
            target.bind();
            render::RenderSettings settings;
            settings.cull =
                false; // the whole extent is drawn: holes anywhere are visible to the check
            settings.epsilon_px = 1.0;
            const int frames = 60;
            int frames_with_missing = 0, missing_total = 0;
            for (int k = 0; k < frames; ++k) {
                const render::FrameStats stats =
                    renderer.draw(flyover(renderer, k, frames), settings);
                ASSERT_EQ(holesOrOverlaps(scene.reader->geometry(), renderer.lastDrawnPatches()),
                          0u)
                    << codec << " frame " << k;
                EXPECT_LE(stats.resident, 24);
                EXPECT_LE(renderer.streamingCacheBytes(),
                          size_t(0.25 * 1024 * 1024) + 6 * 33 * 33 * 2 + 4096);
                frames_with_missing += stats.missing > 0;
                missing_total += stats.missing;
            }
            std::printf(
                "%s, prefetch %d frames: %d of %d frames had patches still coming (%d in all)\n",
                codec, prefetch, frames_with_missing, frames, missing_total);
            EXPECT_GT(frames_with_missing, 0)
                << "the budget must force fallbacks for this test to mean anything";
            EXPECT_TRUE(renderer.streamingError().empty());
        }
}

TEST(Streaming, ATeleportReachesFullDetailWithinBoundedFramesOnceTheWorkersAreDone)
{
    StreamingScene scene("progressive");
    render::RendererOptions options;
    options.streaming = true;
    options.uploads_per_frame = 8;
    // The count is the budget under test; on llvmpipe the GPU passes run on the CPU inside
    // the upload time, which would otherwise decide.
    options.upload_budget_ms = 1e9;
    render::TerrainRenderer renderer(*scene.reader, options);
    gpu::RenderTarget target(320, 180, 1);
    target.bind();
    const lod::Camera far_view = renderer.defaultCamera({320, 180});
    const lod::Camera close_view = flyover(renderer, 30, 60);
    render::RenderSettings settings;
    settings.texel_px = 0.0; // the LOD of ε alone, which the bounds below were measured with
    for (const lod::Camera& cam : {far_view, close_view}) {
        render::FrameStats stats = renderer.draw(cam, settings);
        EXPECT_GT(stats.missing, 0) << "right after the jump the new detail is not there yet";
        const int desired = stats.missing; // a lower bound of what has to arrive
        int frames = 1;
        while (stats.missing > 0 && frames < 100) {
            renderer.waitForStreaming(); // I/O done ...
            stats = renderer.draw(cam, settings);
            ++frames;
        }
        EXPECT_EQ(stats.missing, 0);
        // ... then each frame uploads up to 8 patches; a request round per level of depth.
        const int bound = scene.reader->geometry().levelCount() + (desired + 7) / 8 + 2;
        EXPECT_LE(frames, bound) << "frames to full detail";
    }
}

TEST(Streaming, FullDetailMatchesTheSynchronousRenderer)
{
    StreamingScene scene("lossless");
    render::RendererOptions streaming;
    streaming.streaming = true;
    // Short fades: what is compared is full detail, after arrivals have faded in.
    streaming.arrival_blend.max_frames = 16;
    render::TerrainRenderer a(*scene.reader, streaming);
    render::TerrainRenderer b(*scene.reader);
    gpu::RenderTarget target(320, 180, 1);
    target.bind();
    const lod::Camera cam = flyover(a, 20, 60);
    render::FrameStats stats = a.draw(cam, {});
    // At least one upload a frame, more within the time budget: on a loaded machine the
    // budget admits one, so the bound is in frames, generous (a converged run stops early).
    // Then arrivals finish fading in (at most arrival_blend.max_frames more).
    for (int k = 0; k < 400 && (stats.missing > 0 || stats.fading > 0); ++k) {
        a.waitForStreaming();
        stats = a.draw(cam, {});
    }
    ASSERT_EQ(stats.missing, 0);
    ASSERT_EQ(stats.fading, 0);
    b.draw(cam, {});
    auto sorted = [](std::vector<PatchId> v) {
        std::sort(v.begin(), v.end(), [](PatchId p, PatchId q) {
            return std::tie(p.level, p.y, p.x) < std::tie(q.level, q.y, q.x);
        });
        return v;
    };
    EXPECT_EQ(sorted(a.lastDrawnPatches()), sorted(b.lastDrawnPatches()));
    // Same patches, same triangles.
    const render::CapturedSurface sa = a.capture(cam, {}), sb = b.capture(cam, {});
    EXPECT_EQ(sa.vertices.size(), sb.vertices.size());
}

namespace {

// Streams `cam` to full detail and checks that every drawn patch's resident codes and λ are
// the CPU decoder's, bit for bit, and that the skirts' λ max is the true one once read back.
void expectResidentDataIsTheCpuDecoding(const archive::ArchiveReader& reader, bool gpu,
                                        const char* what)
{
    render::RendererOptions options;
    options.streaming = true;
    options.gpu_reconstruction = gpu;
    options.refine_steps_per_frame = 0; // refinable codecs decode fully: the CPU's codes
    render::TerrainRenderer renderer(reader, options);
    gpu::RenderTarget target(320, 180, 1);
    target.bind();
    const lod::Camera cam = flyover(renderer, 25, 60);
    render::FrameStats stats = renderer.draw(cam, {});
    int reconstructed = stats.reconstructed;
    for (int k = 0; k < 400 && stats.missing > 0; ++k) {
        renderer.waitForStreaming();
        stats = renderer.draw(cam, {});
        reconstructed += stats.reconstructed;
    }
    ASSERT_EQ(stats.missing, 0) << what << " " << renderer.streamingError();
    if (gpu)
        EXPECT_GT(reconstructed, 10) << what << ": the GPU path must be the one taken";
    else
        EXPECT_EQ(reconstructed, 0) << what;
    for (int k = 0; k < 3; ++k)
        renderer.draw(cam, {}); // λ maxima derived on the GPU are read back a frame later
    stream::PatchLoader cpu(reader);
    size_t patches = 0, codes_differing = 0, lambda_differing = 0, lambda_max_wrong = 0;
    const int levels = std::min(reader.blockLayout().levels(), 4);
    for (PatchId p : renderer.lastDrawnPatches()) {
        const auto expected = cpu.load(p);
        const std::vector<uint16_t> codes = renderer.residentCodes(p);
        const std::vector<float> lambda = renderer.residentBlockErrors(p);
        ASSERT_EQ(codes.size(), expected->codes.size()) << what;
        for (size_t k = 0; k < codes.size(); ++k)
            codes_differing += codes[k] != expected->codes[k];
        float lambda_max = 0.f;
        for (size_t k = 0; k < lambda.size(); ++k)
            if (int(k % size_t(reader.blockLayout().levels())) < levels) {
                lambda_differing += lambda[k] != expected->block_errors[k];
                lambda_max = std::max(lambda_max, expected->block_errors[k]);
            }
        const lod::PatchBounds& b = renderer.quadtree().bounds(p);
        const float cap = b.max_height - b.min_height;
        lambda_max_wrong += renderer.residentLambdaMax(p) != double(std::min(lambda_max, cap));
        ++patches;
    }
    EXPECT_GT(patches, 10u) << what;
    EXPECT_EQ(codes_differing, 0u) << what;
    EXPECT_EQ(lambda_differing, 0u) << what;
    EXPECT_EQ(lambda_max_wrong, 0u) << what;
    EXPECT_TRUE(renderer.streamingError().empty()) << renderer.streamingError();
}

} // namespace

TEST(Streaming, GpuReconstructionLeavesTheCpuDecodersCodesAndBlockErrorsResident)
{
    for (const std::string& codec : test::gpuDecodedCodecs()) {
        StreamingScene scene(codec);
        expectResidentDataIsTheCpuDecoding(*scene.reader, true,
                                           (codec + ", λ derived on the GPU").c_str());
        expectResidentDataIsTheCpuDecoding(*scene.reader, false,
                                           (codec + ", decoded on the CPU").c_str());
    }
    // λ stored in the archive: uploaded, not derived.
    auto context = gpu::HeadlessContext::create();
    test::ScratchDir dir;
    BuildOptions build;
    build.patch_size = 33;
    build.codec = "progressive";
    build.max_error = 2.0;
    build.store_block_errors = true;
    build.progress = {};
    const std::string stored = dir.path("stored.ridge");
    buildArchive(test::dataPath("everest_crop.tif"), stored, build);
    const archive::ArchiveReader reader(stored);
    expectResidentDataIsTheCpuDecoding(reader, true, "progressive, λ stored");
}

// The fractal-rings paper's "Base incremental", for every refinable codec: from afar, patches
// are decoded with fewer steps than their full decode (what is drawn differs from it); as the
// camera comes down to the terrain, resident patches are refined in place within the per-frame
// step budget.
TEST(Streaming, BaseIncrementalDecodesFarPatchesPartiallyAndRefinesThemAsTheViewerApproaches)
{
    size_t tested = 0;
    for (const std::string& codec : test::gpuDecodedCodecs()) {
        if (!makeCodec(codec, 1.0, 5)->capabilities().gpu.refinable)
            continue;
        ++tested;
        StreamingScene scene(codec);
        render::RendererOptions options;
        options.streaming = true;
        options.refine_steps_per_frame = 1; // one iteration a frame: refinement must queue
        render::TerrainRenderer renderer(*scene.reader, options);
        gpu::RenderTarget target(320, 180, 1);
        target.bind();
        render::RenderSettings settings;
        settings.epsilon_px = 4.0;
        const lod::TerrainFrame& f = renderer.quadtree().frame();
        const auto camera = [&](double height) {
            const double x = f.extentX() * 0.5, y = f.extentY() * 0.5;
            const double ground = renderer.groundHeight(x, y);
            const glm::dvec3 pos(x - 0.3 * height, y - 0.3 * height, ground + height);
            double near_m, far_m;
            renderer.clipPlanesFor(pos, near_m, far_m);
            return lod::Camera(pos, glm::dvec3(x, y, ground), 60.0, {320, 180}, near_m, far_m);
        };
        // Far: everything resident, then count the patches drawn from a partial decode.
        const lod::Camera far = camera(60000.0);
        render::FrameStats stats = renderer.draw(far, settings);
        for (int k = 0; k < 400 && stats.missing > 0; ++k) {
            renderer.waitForStreaming();
            stats = renderer.draw(far, settings);
        }
        ASSERT_EQ(stats.missing, 0) << codec;
        stream::PatchLoader cpu(*scene.reader);
        size_t partial = 0;
        for (PatchId p : renderer.lastDrawnPatches())
            partial += renderer.residentCodes(p) != cpu.load(p)->codes;
        EXPECT_GT(partial, 0u) << codec << ": far patches decoded with fewer steps";
        // Down to the terrain: refinement in place, never more steps a frame than the budget.
        int refined = 0;
        for (int k = 0; k <= 40; ++k) {
            renderer.waitForStreaming();
            stats = renderer.draw(camera(60000.0 * std::pow(0.85, k)), settings);
            EXPECT_LE(stats.refine_steps, 1) << codec << " frame " << k;
            refined += stats.refined;
        }
        EXPECT_GT(refined, 0) << codec << ": resident patches refined as the viewer approached";
        // Held still, the queue drains: no patch is drawn short of its iterations.
        const lod::Camera still = camera(60000.0 * std::pow(0.85, 40));
        for (int k = 0; k < 400 && (stats.under_refined > 0 || stats.missing > 0); ++k) {
            renderer.waitForStreaming();
            stats = renderer.draw(still, settings);
        }
        EXPECT_EQ(stats.under_refined, 0) << codec;
        EXPECT_EQ(stats.missing, 0) << codec;
        EXPECT_TRUE(renderer.streamingError().empty()) << renderer.streamingError();
    }
    EXPECT_GT(tested, 0u) << "a refinable codec is registered";
}

TEST(Streaming, TheUploadByteBudgetLimitsEachFrameButNeverStopsProgress)
{
    StreamingScene scene("progressive");
    render::RendererOptions options;
    options.streaming = true;
    options.upload_budget_mb = 1e-6; // less than one patch: one upload per frame
    options.upload_budget_ms = 1e9;
    render::TerrainRenderer renderer(*scene.reader, options);
    gpu::RenderTarget target(320, 180, 1);
    target.bind();
    const lod::Camera cam = flyover(renderer, 40, 60);
    render::FrameStats stats = renderer.draw(cam, {});
    int frames = 1;
    uint64_t uploaded = stats.bytes_uploaded, read = stats.bytes_read;
    while (stats.missing > 0 && frames < 400) {
        renderer.waitForStreaming();
        stats = renderer.draw(cam, {});
        EXPECT_LE(stats.loaded, 1) << "frame " << frames;
        uploaded += stats.bytes_uploaded;
        read += stats.bytes_read;
        ++frames;
    }
    EXPECT_EQ(stats.missing, 0) << "one patch a frame still converges";
    EXPECT_GT(frames, 5);
    EXPECT_GT(uploaded, 0u);
    EXPECT_GT(read, 0u);
}

TEST(Streaming, NormalsAgreeAcrossEverySameLevelSeamWhateverOrderPatchesArrivedIn)
{
    for (const char* codec : {"lossless", "progressive"}) {
        StreamingScene scene(codec);
        const PyramidGeometry& g = scene.reader->geometry();
        const int n = g.patchSize();
        for (const bool seamless : {true, false}) {
            render::RendererOptions options;
            options.streaming = true;
            options.uploads_per_frame = 2; // arrivals spread over many frames, in any order
            options.seamless_normals = seamless;
            render::TerrainRenderer renderer(*scene.reader, options);
            gpu::RenderTarget target(320, 180, 1);
            target.bind();
            render::RenderSettings settings;
            settings.cull = false;
            const lod::Camera cam = flyover(renderer, 30, 60);
            render::FrameStats stats = renderer.draw(cam, settings);
            for (int k = 0; k < 200 && stats.missing > 0; ++k) {
                renderer.waitForStreaming();
                stats = renderer.draw(cam, settings);
            }
            ASSERT_EQ(stats.missing, 0);
            // Every shared border column or row of two drawn same-level neighbours.
            std::set<std::tuple<int, int, int>> drawn;
            for (PatchId p : renderer.lastDrawnPatches())
                drawn.insert({p.level, p.x, p.y});
            size_t seams = 0, differing = 0;
            for (PatchId p : renderer.lastDrawnPatches())
                for (const auto& [dx, dy] : {std::pair{1, 0}, std::pair{0, 1}}) {
                    const PatchId q{p.level, p.x + dx, p.y + dy};
                    if (!drawn.count({q.level, q.x, q.y}))
                        continue;
                    const std::vector<int8_t> a = renderer.residentNormals(p),
                                              b = renderer.residentNormals(q);
                    // The seam's end samples also border a third patch (which may be a
                    // coarser one, so missing on one side): inner samples only.
                    for (int k = 1; k < n - 1; ++k) {
                        // East seam: p's column n−1 is q's column 0; south: rows likewise.
                        const size_t ia = dx ? size_t(k) * n + (n - 1) : size_t(n - 1) * n + k;
                        const size_t ib = dx ? size_t(k) * n : size_t(k);
                        for (int c = 0; c < 3; ++c)
                            differing += a[ia * 4 + c] != b[ib * 4 + c];
                    }
                    ++seams;
                }
            EXPECT_GT(seams, 4u) << codec;
            if (seamless)
                EXPECT_EQ(differing, 0u) << codec << ": " << seams << " seams";
            else
                EXPECT_GT(differing, 0u) << codec << ": one-sided borders must differ somewhere";
        }
    }
}
