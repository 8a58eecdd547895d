// Scheme "chunked"'s own promises, with each of its options: Ulrich's simplified chunks
// (meshes=on, the default) and full grids (meshes=off) are watertight and meet ε, at the
// terrain's clipped borders too, and simplified chunks stream without holes.
#include "streaming_checks.h"
#include "terrain_border_checks.h"
#include "terrain_renderer_fixture.h"

#include "ridge/gpu/render_target.h"

#include <gtest/gtest.h>

#include <map>

using namespace ridge;

namespace {

class ChunkedScheme : public test::TerrainRendererTest {};

} // namespace

TEST_F(ChunkedScheme, SimplifiedAndFullGridChunksAreWatertightAndWithinEpsilon)
{
    // The chunks add no error beyond what their selection accounts for: simplified chunks
    // select at 1.5·Err(P) and drop at most Err(P)/2 (how far they simplify is lod's
    // ChunkMesh tests' and the Sierra benchmark's); full-grid chunks draw the level's samples.
    // Both must meet ε itself (no fine-LOD excess), and not fall far below it. Progressive: the
    // finest level has Err > 0, so even its chunks are simplified.
    struct Case {
        std::string name, codec;
        double max_error;
        std::string spec;
        double epsilon_px = 2.0;
    };
    const std::string simplified = "chunked", grid = "chunked,meshes=off";
    std::map<std::string, size_t> patches; // drawn, over all cameras
    for (const Case& c :
         {Case{"simplified chunks", "lossless", 0.0, simplified},
          Case{"full-grid chunks", "lossless", 0.0, grid},
          Case{"progressive simplified chunks", "progressive", 1.0, simplified},
          Case{"progressive full-grid chunks", "progressive", 1.0, grid},
          // Coarse: big simplified triangles meet the terrain's clipped east and south border.
          Case{"simplified chunks at ε 8", "lossless", 0.0, simplified, 8.0},
          Case{"progressive simplified chunks at ε 8", "progressive", 1.0, simplified, 8.0}}) {
        const test::Scene s = scene(c.codec, c.max_error, {c.spec});
        const double worst =
            worstErrorOverRandomCameras(s, "chunked", c.epsilon_px, c.name, patches[c.name]);
        EXPECT_LE(worst, c.epsilon_px * 1.001) << c.name;
        EXPECT_GT(worst, c.epsilon_px / 4) << c.name << ", and not far below ε";
    }
    // Their own error in the selection refines further than the full grids.
    EXPECT_GT(patches["simplified chunks"], patches["full-grid chunks"]);
    EXPECT_GT(patches["progressive simplified chunks"], patches["progressive full-grid chunks"]);
}

TEST_F(ChunkedScheme, EveryVertexIsASampleOfItsLevelWithItsHeight)
{
    // Full grids draw every sample of the patch's level; simplified chunks a subset of them:
    // either way each surface vertex is a sample, at that level's decoded height (what a pick
    // on a full-grid chunk returns at a sample).
    for (const std::string spec : {"chunked,meshes=off", "chunked"}) {
        const test::Scene s = scene("lossless", 0.0, {spec});
        const auto cameras = randomCameras(*s.renderer, 4, {320, 180}, 7);
        for (size_t k = 0; k < cameras.size(); ++k) {
            render::RenderSettings settings;
            settings.scheme = "chunked";
            settings.epsilon_px = 4.0;
            const render::CapturedSurface surface = s.renderer->capture(cameras[k], settings);
            const GridVertices v = gridVertices(s, surface);
            EXPECT_GT(v.all, 0u) << spec << ", camera " << k;
            EXPECT_GT(v.on_grid, v.all * 9 / 10) << spec << ", camera " << k;
            EXPECT_EQ(v.off_height, 0u) << spec << ", camera " << k;
        }
    }
}

TEST_F(ChunkedScheme, CoarseLevelsReachTheEastAndSouthBorder)
{
    // Everest is 301 x 203: W − 1 = 300 and H − 1 = 202 are multiples of neither 8 nor 16,
    // the steps of its coarse levels with patches of 33 (5 levels) and 65 (4 levels).
    struct Case {
        int patch_size;
        std::string spec;
        const char* name;
    };
    for (const Case& c : {Case{33, "chunked,meshes=off", "full-grid chunks, patches of 33"},
                          Case{33, "chunked", "simplified chunks, patches of 33"},
                          Case{65, "chunked", "simplified chunks, patches of 65"}}) {
        test::Scene s =
            test::openScene(test::buildEverestArchive(*scratch_, "lossless", c.patch_size), c.spec);
        const test::Counts n = test::checkBorders(s, c.name);
        // The cameras must draw levels that end short of the border, or nothing was tested.
        EXPECT_GE(n.short_borders, 2u) << c.name;
    }
}

TEST_F(ChunkedScheme, FlatSeaPatchesAreClosed)
{
    // Flat sea patches have Err(P) = 0 and exact chunks: their skirts hang only the margin.
    for (const auto& [spec, name] :
         {std::pair<std::string, std::string>{"chunked,meshes=off", "sea, full-grid chunks"},
          {"chunked", "sea, simplified chunks"}}) {
        test::Scene s = test::openScene(test::seaArchive(*scratch_), spec);
        const test::Counts n = test::checkBorders(s, name);
        EXPECT_GE(n.short_borders, 4u) << name;
        // With the texture-detail criterion flat sea patches of different levels meet, closed
        // by skirts as thin as float rounding allows (233 open edges from 760 km up before the
        // skirt margin followed the camera's distance).
        test::checkBorders(s, name + ", texel 1 px", 1.0);
    }
}

TEST(ChunkedSchemeStreaming, SimplifiedChunksStreamWithoutHolesAndConvergeToAWatertightSurface)
{
    // The chunked baseline under streaming: its chunks are built by the decode workers, each
    // slot's budget counts a full-grid index buffer, and the result is as sound as the
    // synchronous renderer's.
    for (const char* codec : {"lossless", "progressive"}) {
        test::StreamingScene scene(codec);
        render::RendererOptions options;
        options.streaming = true;
        options.schemes = {"chunked,meshes=on"};
        options.synchronous_stats = true; // this frame's triangles
        // 24 slots of 33² patches: textures plus a 16-bit index buffer of the full grid.
        options.vram_budget_mb = 24 * (7815.0 + (6 * 32 * 32 + 24 * 32) * 2) / (1024 * 1024);
        options.ram_budget_mb = 0.5;
        options.uploads_per_frame = 3;
        render::TerrainRenderer renderer(*scene.reader, options);
        ASSERT_EQ(renderer.residentSlots(), 24);
        gpu::RenderTarget target(320, 180, 1);
        target.bind();
        render::RenderSettings settings;
        settings.scheme = "chunked";
        settings.cull = false;
        settings.epsilon_px = 1.0;
        const int frames = 40;
        for (int k = 0; k < frames; ++k) {
            const render::FrameStats stats =
                renderer.draw(test::flyover(renderer, k, frames), settings);
            ASSERT_EQ(test::holesOrOverlaps(scene.reader->geometry(), renderer.lastDrawnPatches()),
                      0u)
                << codec << " frame " << k;
            EXPECT_LE(stats.resident, 24);
            EXPECT_GT(stats.triangles, 0u);
        }
        const lod::Camera cam = test::flyover(renderer, frames / 2, frames);
        settings.cull_blocks = false;
        render::FrameStats stats = renderer.draw(cam, settings);
        for (int k = 0; k < 200 && stats.missing > 0; ++k) {
            renderer.waitForStreaming();
            stats = renderer.draw(cam, settings);
        }
        EXPECT_EQ(stats.missing, 0) << codec;
        const render::CapturedSurface surface = renderer.capture(cam, settings);
        const test::WatertightReport w =
            test::checkWatertight(surface, renderer.quadtree().frame());
        EXPECT_GT(w.triangles, 0u);
        EXPECT_EQ(w.open_edges, 0u) << codec << ": " << w.first_problem;
        EXPECT_EQ(w.uncovered_seams, 0u) << codec << ": " << w.first_problem;
        EXPECT_TRUE(renderer.streamingError().empty());
    }
}
