// Vertical exaggeration at render time (RenderSettings::exaggeration, issue 22): every
// registered scheme draws the surface k times as tall, and selection, tessellation, culling
// and skirts measure that surface, so the scheme's promises hold on what is drawn — captured
// surfaces watertight and every finest sample (its height times k) within ε on screen. The
// same cameras and ε with the exaggeration left out of selection (k only in the shaders)
// would under-refine by up to k.
#include "captured_surface_checks.h"
#include "fixture_archives.h"

#include "ridge/gpu/context.h"
#include "ridge/pipeline/level_decoder.h"
#include "ridge/render/terrain_renderer.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <random>

namespace ridge {
namespace {

constexpr double kK = 3.0;

class Exaggeration : public ::testing::TestWithParam<std::string> {
  protected:
    static void SetUpTestSuite()
    {
        context_ = gpu::HeadlessContext::create().release();
        scratch_ = new test::ScratchDir();
        reader_ = new archive::ArchiveReader(test::buildEverestArchive(*scratch_, "lossless", 33));
        render::RendererOptions ro;
        ro.synchronous_stats = true;
        ro.max_resident_patches = 2048;
        ro.schemes = render::lodSchemeNames();
        renderer_ = new render::TerrainRenderer(*reader_, ro);
        const CodeGrid finest = decodeLevel(*reader_, reader_->geometry().finestLevel());
        for (uint16_t c : finest.codes) // the drawn surface's samples: k times the heights
            exaggerated_.push_back(float(kK * reader_->quantization().toMetres(c)));
    }
    static void TearDownTestSuite()
    {
        delete renderer_;
        delete reader_;
        delete scratch_;
        delete context_;
    }

    // Cameras placed in the exaggerated space: 40 m .. 8 km above the drawn ground, looking
    // at drawn points of the terrain.
    static std::vector<lod::Camera> cameras(int count, lod::Viewport vp)
    {
        const lod::TerrainFrame& f = renderer_->quadtree().frame();
        std::mt19937 rng(11);
        std::uniform_real_distribution<double> u(0.0, 1.0);
        std::vector<lod::Camera> out;
        while (int(out.size()) < count) {
            const double x = (0.05 + 0.9 * u(rng)) * f.extentX(),
                         y = (0.05 + 0.9 * u(rng)) * f.extentY();
            const glm::dvec3 pos(
                x, y, renderer_->groundHeight(x, y, kK) + 40.0 * std::pow(200.0, u(rng)));
            const double tx = u(rng) * f.extentX(), ty = u(rng) * f.extentY();
            const glm::dvec3 at(tx, ty, renderer_->groundHeight(tx, ty, kK));
            if (glm::length(at - pos) < 1.0)
                continue;
            double near_m, far_m;
            renderer_->clipPlanesFor(pos, near_m, far_m, kK);
            out.emplace_back(pos, at, 60.0, vp, near_m, far_m);
        }
        return out;
    }

    static gpu::HeadlessContext* context_;
    static test::ScratchDir* scratch_;
    static archive::ArchiveReader* reader_;
    static render::TerrainRenderer* renderer_;
    static std::vector<float> exaggerated_;
};

gpu::HeadlessContext* Exaggeration::context_ = nullptr;
test::ScratchDir* Exaggeration::scratch_ = nullptr;
archive::ArchiveReader* Exaggeration::reader_ = nullptr;
render::TerrainRenderer* Exaggeration::renderer_ = nullptr;
std::vector<float> Exaggeration::exaggerated_;

} // namespace

TEST_P(Exaggeration, TheExaggeratedSurfaceIsWatertightAndWithinEpsilon)
{
    const lod::Viewport vp{320, 180};
    const lod::TerrainFrame& frame = renderer_->quadtree().frame();
    double worst = 0.0;
    const double epsilon = 2.0;
    const render::SchemePromises promises = render::lodSchemePromises(GetParam());
    for (const lod::Camera& camera : cameras(8, vp)) {
        render::RenderSettings settings;
        settings.scheme = GetParam();
        settings.epsilon_px = epsilon;
        settings.texel_px = 0.0; // ε alone decides, as the promise is about ε
        settings.exaggeration = kK;
        const test::SeamReport w = test::checkSeamsAsPromised(*renderer_, camera, settings, frame);
        EXPECT_EQ(w.problems, 0u) << w.first_problem;
        const test::ScreenErrorReport e = test::measureScreenSpaceError(
            renderer_->capture(camera, settings), frame, exaggerated_, camera);
        EXPECT_GT(e.samples, 0u);
        EXPECT_EQ(e.uncovered, 0u);
        if (promises.screen_space_error) {
            EXPECT_LE(e.max_px, epsilon * 1.001 + 1e-3) << e.max_px / epsilon << " ε";
        }
        worst = std::max(worst, e.max_px / epsilon);
    }
    std::printf("[%s] exaggeration %.0f: measured screen-space error at most %.3f ε (%s)\n",
                GetParam().c_str(), kK, worst,
                promises.screen_space_error ? "promised ≤ ε" : "measured only");
}

TEST_P(Exaggeration, EveryDrawnVertexIsKTimesTheTrueSurface)
{
    // Each captured surface vertex, its height divided by k, lies on the true terrain within
    // the root's Err(P) (what any level may deviate) — had k been left out of the vertices, a
    // 6,000 m slope would be 4,000 m off.
    const lod::TerrainFrame& f = renderer_->quadtree().frame();
    const double cx = 0.5 * f.extentX(), cy = 0.5 * f.extentY();
    render::RenderSettings settings;
    settings.scheme = GetParam();
    settings.exaggeration = kK;
    const glm::dvec3 pos(cx, cy - 20000.0, kK * 9000.0 + 20000.0);
    double near_m, far_m;
    renderer_->clipPlanesFor(pos, near_m, far_m, kK);
    const lod::Camera camera(pos, {cx, cy, kK * 5000.0}, 60.0, {320, 180}, near_m, far_m);
    const render::CapturedSurface s = renderer_->capture(camera, settings);
    const double bound = renderer_->quadtree().bounds({0, 0, 0}).err + 1e-3;
    const int w = f.geometry().width(), h = f.geometry().height();
    auto at = [&](int i, int j) {
        return double(exaggerated_[size_t(std::clamp(j, 0, h - 1)) * w +
                                   size_t(std::clamp(i, 0, w - 1))]) /
               kK;
    };
    size_t checked = 0;
    double worst = 0.0;
    for (const render::CapturedVertex& v : s.vertices) {
        if (v.skirt != 0)
            continue;
        const double x = v.x + s.camera_position.x, y = v.y + s.camera_position.y;
        const double col = f.columnOf(x), row = f.rowOf(y);
        const int i = int(std::floor(col)), j = int(std::floor(row));
        const double tx = col - i, ty = row - j;
        const double truth = (at(i, j) * (1 - tx) + at(i + 1, j) * tx) * (1 - ty) +
                             (at(i, j + 1) * (1 - tx) + at(i + 1, j + 1) * tx) * ty;
        const double drawn = (double(v.z) + s.camera_position.z) / kK;
        worst = std::max(worst, std::abs(drawn - truth));
        ++checked;
    }
    EXPECT_GT(checked, 100u);
    EXPECT_LE(worst, bound) << "metres off the true surface, after dividing by k";
}

INSTANTIATE_TEST_SUITE_P(EveryScheme, Exaggeration, ::testing::ValuesIn(render::lodSchemeNames()),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                             return info.param;
                         });

} // namespace ridge
