// Normal maps on a projected grid (patch_normals.comp's projected branch, PatchTextures::
// computeNormalsOnGrid): computed in the grid's own axes and turned to east, north, up
// through the grid's tangents on the lattice. Held to the CPU's normals of the same heights
// placed by the terrain frame, on a polar stereographic grid round the South Pole, where the
// grid's columns point every way of the compass (a map left in grid axes is off by up to
// 180° there).
#include "gdal_translate.h"
#include "patch_textures.h"
#include "test_support.h"

#include "ridge/gpu/context.h"
#include "ridge/lod/archive_frame.h"
#include "ridge/lod/edge_tessellation.h"
#include "ridge/pipeline/build.h"
#include "ridge/stream/patch_loader.h"

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace ridge {
namespace {

TEST(ProjectedNormals, AreTheSurfacesNormalsInEastNorthUpRoundThePole)
{
    const auto context = gpu::HeadlessContext::create();
    test::ScratchDir dir;
    const std::string tif = dir.path("polar.tif");
    test::gdalTranslate(test::dataPath("everest_utm45.tif"), tif,
                        {"-a_srs", "EPSG:3031", "-a_ullr", "-11790", "8865", "11790", "-8865"});
    const std::string path = dir.path("polar.ridge");
    BuildOptions options;
    options.patch_size = 33;
    options.progress = {};
    buildArchive(tif, path, options);
    const archive::ArchiveReader reader(path);
    const lod::TerrainFrame frame = lod::terrainFrameOf(reader, lod::FrameChoice::Ellipsoid, path);
    ASSERT_NE(frame.projectedGrid(), nullptr);
    const PyramidGeometry& g = reader.geometry();
    const TessellationBlockLayout layout = reader.blockLayout();
    render::PatchTextures textures(g.patchSize(), layout,
                                   std::min(layout.levels(), lod::kMaxBlockLevels), 2,
                                   reader.quantization());
    textures.setGridAxes(*frame.projectedGrid());
    stream::PatchLoader loader(reader);
    const glm::dvec2 pole(130.5, 98.0); // sample centre (0, 0) in EPSG:3031
    // The finest patch holding the pole and the level above's.
    for (const int level : {g.finestLevel(), g.finestLevel() - 1}) {
        const int64_t step = g.step(level), span = int64_t(g.cells()) * step;
        const PatchId p{level, int(pole.x / double(span)), int(pole.y / double(span))};
        const std::shared_ptr<const stream::DecodedPatch> patch = loader.load(p);
        textures.upload(*patch, 0, 1e4f);
        textures.finishUploads();
        textures.computeNormalsOnGrid(0, {-1, -1, -1, -1}, p.x * span, p.y * span, step);
        glMemoryBarrier(GL_ALL_BARRIER_BITS);
        const std::vector<int8_t> got = textures.readNormals(0);
        const int n = g.patchSize();
        auto metres = [&](int i, int j) {
            return reader.quantization().toMetres(patch->codes[size_t(j) * n + i]);
        };
        double worst = 0.0, worst_near_pole = 0.0;
        size_t compared = 0;
        for (int j = 1; j + 1 < n; ++j)
            for (int i = 1; i + 1 < n; ++i) {
                const double c = double(p.x * span + i * step), r = double(p.y * span + j * step);
                if (c >= g.width() - 1 || r >= g.height() - 1)
                    continue;
                const glm::dvec3 t_i = frame.worldOf(c + step, r, metres(i + 1, j)) -
                                       frame.worldOf(c - step, r, metres(i - 1, j));
                const glm::dvec3 t_j = frame.worldOf(c, r + step, metres(i, j + 1)) -
                                       frame.worldOf(c, r - step, metres(i, j - 1));
                glm::dvec3 world = glm::normalize(glm::cross(t_i, t_j));
                if (glm::dot(world, frame.upAt(c, r)) < 0.0)
                    world = -world;
                const glm::dvec3 expected = glm::transpose(frame.basisAt(c, r).matrix()) * world;
                const int8_t* t = &got[(size_t(j) * n + i) * 4];
                const glm::dvec3 gpu = glm::normalize(glm::dvec3(t[0], t[1], t[2]));
                const double angle = std::acos(std::clamp(glm::dot(gpu, expected), -1.0, 1.0));
                worst = std::max(worst, angle);
                if (glm::length(glm::dvec2(c, r) - pole) < 4.0)
                    worst_near_pole = std::max(worst_near_pole, angle);
                ++compared;
            }
        std::printf("level %d: %zu normals within %.4f rad of the CPU's (within 4 samples of "
                    "the pole: %.4f rad)\n",
                    level, compared, worst, worst_near_pole);
        EXPECT_GT(compared, 90u);
        // RGBA8_SNORM holds a component to 1/254: about 0.01 rad.
        EXPECT_LT(worst, 0.02) << "level " << level;
    }
}

} // namespace
} // namespace ridge
