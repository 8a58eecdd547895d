// The popping metric measured on the GPU (TerrainRenderer::measureFramePopping, plane frames)
// against the CPU measure it stands in for (render::measurePopping over surfaceHeightsAtSamples
// of two captures), for every registered scheme. The sweep along a fly-over is in the
// conformance suite (SchemeConformance.LodChangesPop...), which compares the two measures on
// every frame too.
#include "terrain_renderer_fixture.h"

#include "ridge/render/frame_measures.h"

namespace ridge {
namespace {

class PoppingOnGpu : public test::TerrainRendererTest {};

render::RenderSettings settingsFor(const std::string& scheme)
{
    render::RenderSettings s;
    s.scheme = scheme;
    s.epsilon_px = 2.0;
    s.texel_px = 0.0;
    s.cull_blocks = false; // whole patches: block culling follows the camera that looks
    return s;
}

// A low camera drawn with the LOD state of a far one: coarse patches under a near view, a
// large displacement to measure.
TEST_F(PoppingOnGpu, EqualsTheCpuMeasureOfTheSameTwoSurfacesForEveryScheme)
{
    const test::Scene s = scene("lossless");
    render::TerrainRenderer& r = *s.renderer;
    const lod::TerrainFrame& f = r.quadtree().frame();
    const lod::Viewport vp{240, 160};
    const glm::dvec3 at(0.55 * f.extentX(), 0.5 * f.extentY(),
                        r.groundHeight(0.55 * f.extentX(), 0.5 * f.extentY()));
    const glm::dvec3 near_pos = at + glm::dvec3(-0.2 * f.extentX(), -0.1 * f.extentY(), 1500.0);
    const glm::dvec3 far_pos = at + glm::dvec3(-2.0 * f.extentX(), -1.0 * f.extentY(), 3e4);
    const lod::Camera cam = r.cameraLookingAt(near_pos, at, 60.0, vp);
    const lod::Camera far_cam = r.cameraLookingAt(far_pos, at, 60.0, vp);
    double largest = 0.0;
    for (const std::string& scheme : render::lodSchemeNames()) {
        SCOPED_TRACE(scheme);
        const render::RenderSettings settings = settingsFor(scheme);
        // Both LOD states resident (synchronous loads), then each measure of the same pair.
        r.capture(far_cam, settings);
        const render::SampleHeights before =
            render::surfaceHeightsAtSamples(r.capture(cam, settings, &far_cam, true), f);
        const render::SampleHeights after =
            render::surfaceHeightsAtSamples(r.capture(cam, settings), f);
        const render::PoppingReport cpu = render::measurePopping(before, after, f, cam);
        r.resetPopping();
        EXPECT_EQ(r.measureFramePopping(far_cam, settings).samples, 0u); // the far LOD state
        const render::PoppingReport gpu = r.measureFramePopping(cam, settings);
        std::printf("[%s] popping, far LOD state under a near camera: CPU %.4f px (%zu samples), "
                    "GPU %.4f px (%zu samples, stride %d)\n",
                    scheme.c_str(), cpu.max_px, cpu.samples, gpu.max_px, gpu.samples,
                    gpu.sample_stride);
        EXPECT_EQ(gpu.sample_stride, 1);
        // Rounding: float against double projections; the far surface was captured relative
        // to the far camera (float positions 30 km out: millimetres).
        EXPECT_NEAR(gpu.max_px, cpu.max_px, 0.01 + 1e-3 * cpu.max_px);
        EXPECT_NEAR(gpu.max_metres, cpu.max_metres, 0.01 + 1e-5 * cpu.max_metres);
        // The GPU leaves out a sample at a convex corner of the surface's outline (the nudges
        // point away from it).
        EXPECT_NEAR(double(gpu.samples), double(cpu.samples), 0.005 * double(cpu.samples));
        EXPECT_GT(cpu.samples, 1000u);
        largest = std::max(largest, cpu.max_px);
    }
    // A scheme drawing the finest samples whatever the LOD camera pops 0; the others must not.
    EXPECT_GT(largest, 1.0) << "the two LOD states must differ for the test to mean anything";
}

TEST_F(PoppingOnGpu, TheSameFrameTwiceDoesNotPopAndAResetStartsAfresh)
{
    const test::Scene s = scene("lossless");
    render::TerrainRenderer& r = *s.renderer;
    const lod::Camera cam = r.defaultCamera({200, 120});
    const render::RenderSettings settings = settingsFor(render::defaultLodScheme());
    r.capture(cam, settings);
    EXPECT_EQ(r.measureFramePopping(cam, settings).samples, 0u);
    const render::PoppingReport same = r.measureFramePopping(cam, settings);
    EXPECT_GT(same.samples, 1000u);
    EXPECT_EQ(same.max_px, 0.0);
    r.resetPopping();
    EXPECT_EQ(r.measureFramePopping(cam, settings).samples, 0u);
}

} // namespace
} // namespace ridge
