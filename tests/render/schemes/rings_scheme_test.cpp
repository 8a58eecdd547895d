// Scheme "rings"' own behaviour beyond the conformance suite: the rings drawn at their levels
// around the viewer (the central patch and the first ring at the finest, one level coarser a
// ring), both vertex densities watertight, the central patch following the camera, and
// archives or options the static grids cannot take refused naming the file and the option.
#include "captured_surface_checks.h"
#include "error_expectations.h"
#include "terrain_renderer_fixture.h"

#include "ridge/core/error.h"

#include <gtest/gtest.h>

#include <map>

using namespace ridge;

namespace {

class RingsScheme : public test::TerrainRendererTest {};

} // namespace

TEST_F(RingsScheme, DrawsTheFinestLevelAroundTheViewerAndOneLevelCoarserARing)
{
    for (const std::string spec : {"rings", "rings,rings=3", "rings,vertex-step=2"}) {
        SCOPED_TRACE(spec);
        const test::Scene s = scene("lossless", 0.0, {spec});
        const lod::TerrainFrame& f = s.renderer->quadtree().frame();
        const int finest = s.reader->geometry().finestLevel();
        const double tile = s.reader->geometry().cells() * f.spacingX();
        render::RenderSettings settings;
        settings.scheme = "rings";
        settings.cull = false;
        // Over the tile (2, 2), looking down: that tile is the central patch.
        const glm::dvec3 above(2.5 * tile, f.yOf(2.5 * s.reader->geometry().cells()), 9000.0);
        const lod::Camera camera(above, above + glm::dvec3(1.0, 1.0, -3000.0), 60.0, {320, 200},
                                 1.0, 1e6);
        const render::CapturedSurface surface = s.renderer->capture(camera, settings);
        const test::StitchedReport w = test::checkStitchedWatertight(surface, f);
        EXPECT_EQ(w.open_edges, 0u) << w.first_problem;
        EXPECT_EQ(w.overused_edges, 0u);
        EXPECT_GT(w.degenerate, 0u) << "stitched edges leave degenerate triangles";
        // The patches drawn: the finest level right under the camera, coarser further out.
        std::map<int, int> levels;
        for (const PatchId& p : surface.patches)
            ++levels[p.level];
        EXPECT_GT(levels[finest], 0);
        EXPECT_GT(levels.size(), 2u) << "rings at several levels";
    }
}

TEST_F(RingsScheme, ArchivesAndOptionsTheStaticGridsCannotTakeAreRefusedNamingThem)
{
    // 9-sample patches: 8-cell grids, too few for the Everest crop's 7 levels.
    const std::string small = test::buildEverestArchive(*scratch_, "lossless", 9, 0.0);
    const std::string m = test::errorOf([&] { sceneOf(small, {"rings"}); });
    EXPECT_NE(m.find(small), std::string::npos) << m;
    EXPECT_NE(m.find("patches of 9 samples"), std::string::npos) << m;
    // A renderer built for every scheme leaves out the one that cannot draw the archive.
    const test::Scene all = sceneOf(small, {});
    for (const std::string& name : all.renderer->schemes())
        EXPECT_NE(name, "rings");
    const std::string path = test::buildEverestArchive(*scratch_, "lossless", 33, 0.0);
    EXPECT_NE(test::errorOf([&] { sceneOf(path, {"rings,rings=17"}); }).find("rings=17"),
              std::string::npos);
    EXPECT_NE(test::errorOf([&] { sceneOf(path, {"rings,vertex-step=3"}); }).find("vertex-step=3"),
              std::string::npos);
}
