// Voids kept as holes are never drawn: looking down at the UTM-warped Everest fixture (a
// nodata collar of 5679 samples around the footprint), every scheme draws no pixel whose
// ground lies outside the drawable cells (docs/FORMAT.md, "Validity mask") and leaves no
// hole where the cells are drawable. The ground of a pixel is bracketed on the CPU: its ray
// between the planes of the terrain's lowest and highest height, so a pixel is decided only
// where every point of that segment agrees (no depth precision involved).
#include "test_support.h"

#include "ridge/archive/archive_reader.h"
#include "ridge/gpu/context.h"
#include "ridge/gpu/render_target.h"
#include "ridge/io/raster_source.h"
#include "ridge/pipeline/build.h"
#include "ridge/pyramid/validity_pyramid.h"
#include "ridge/render/terrain_renderer.h"

#include <glm/glm.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

using namespace ridge;

namespace {

struct PixelCounts {
    size_t outside = 0, outside_drawn = 0; // ground wholly over undrawable cells / past the extent
    size_t inside = 0,
           inside_missing = 0; // ground wholly over drawable cells of the coarsest drawn level
};

PixelCounts classify(const render::TerrainRenderer& r, const lod::Camera& cam,
                     const std::vector<float>& depth, const ValidityPyramid& validity)
{
    const lod::TerrainFrame& f = r.quadtree().frame();
    const PyramidGeometry& g = f.geometry();
    const lod::PatchBounds& root = r.quadtree().bounds({0, 0, 0});
    int coarsest = g.finestLevel();
    for (const PatchId& p : r.lastDrawnPatches())
        coarsest = std::min(coarsest, p.level);
    const int64_t step = g.step(coarsest);
    const glm::dmat4 inv = glm::inverse(cam.viewProjection());
    const int w = cam.viewport().width, h = cam.viewport().height;
    PixelCounts c;
    for (int row = 0; row < h; ++row)
        for (int col = 0; col < w; ++col) {
            const double nx = 2.0 * (col + 0.5) / w - 1.0, ny = 1.0 - 2.0 * (row + 0.5) / h;
            glm::dvec4 a = inv * glm::dvec4(nx, ny, -1.0, 1.0),
                       b = inv * glm::dvec4(nx, ny, 0.5, 1.0);
            const glm::dvec3 dir = glm::normalize(glm::dvec3(b) / b.w - glm::dvec3(a) / a.w);
            bool all_outside = true, all_inside = true;
            for (int k = 0; k <= 16; ++k) {
                const double z = root.min_height + (root.max_height - root.min_height) * k / 16.0;
                const double t = (z - cam.position().z) / dir.z;
                const glm::dvec3 ground = cam.position() + t * dir;
                const double column = f.columnOf(ground.x), line = f.rowOf(ground.y);
                const bool in_extent =
                    column >= 0 && line >= 0 && column <= g.width() - 1 && line <= g.height() - 1;
                const int64_t i = int64_t(std::floor(column)), j = int64_t(std::floor(line));
                const bool finest_drawable =
                    in_extent && validity.cellDrawable(g.finestLevel(), i, j);
                const bool coarse_drawable =
                    in_extent && validity.cellDrawable(coarsest, i / step, j / step);
                all_outside &= !finest_drawable;
                all_inside &= coarse_drawable;
            }
            const bool drawn = depth[size_t(row) * w + col] != 0.f; // reverse-Z clears to 0
            if (all_outside) {
                ++c.outside;
                c.outside_drawn += drawn;
            } else if (all_inside) {
                ++c.inside;
                c.inside_missing += !drawn;
            }
        }
    return c;
}

} // namespace

TEST(KeptVoidsRender, NoSchemeDrawsNodataAndNoneLeavesAHoleInTheFootprint)
{
    const std::unique_ptr<gpu::HeadlessContext> context = gpu::HeadlessContext::create();
    test::ScratchDir dir;
    const io::ElevationRaster raster = io::ingestRaster(test::dataPath("everest_utm44.tif"));
    ASSERT_EQ(raster.stats.voids_kept, 5679);
    BuildOptions options;
    options.patch_size = 33;
    options.progress = {};
    const std::string kept = dir.path("kept.ridge");
    buildArchive(raster, kept, options);
    // The same terrain with the collar filled (--fill-voids all): the control that shows the
    // check sees a drawn collar.
    io::ElevationRaster filled = raster;
    filled.nodata.clear();
    filled.stats.voids_filled += filled.stats.voids_kept;
    filled.stats.voids_kept = 0;
    filled.stats.fill_voids = io::VoidFill::All;
    const std::string all = dir.path("all.ridge");
    BuildOptions fill_all = options;
    fill_all.ingest.fill_voids = io::VoidFill::All;
    buildArchive(filled, all, fill_all);

    const lod::Viewport vp{256, 256};
    gpu::RenderTarget target(vp.width, vp.height, 1);
    for (const std::string& scheme : render::lodSchemeNames()) {
        for (const std::string* path : {&kept, &all}) {
            const archive::ArchiveReader reader(*path);
            render::RendererOptions ro;
            ro.synchronous_stats = true;
            ro.schemes = {scheme};
            ro.max_resident_patches = 1024;
            render::TerrainRenderer renderer(reader, ro);
            const lod::TerrainFrame& f = renderer.quadtree().frame();
            const lod::PatchBounds& root = renderer.quadtree().bounds({0, 0, 0});
            const ValidityPyramid validity(raster.nodata, f.geometry(), PyramidFilter::Decimate);
            // Straight down from high above the centre and above each corner's collar, with
            // a narrow field of view: short ground segments per pixel.
            size_t outside = 0, outside_drawn = 0, inside = 0, inside_missing = 0;
            for (const glm::dvec2 at :
                 {glm::dvec2(0.5, 0.5), glm::dvec2(0.1, 0.1), glm::dvec2(0.9, 0.1),
                  glm::dvec2(0.1, 0.9), glm::dvec2(0.9, 0.9)}) {
                const glm::dvec3 target_point(at.x * f.extentX(), at.y * f.extentY(),
                                              root.min_height);
                const double span = at.x == 0.5 ? f.extentX() : 0.3 * f.extentX();
                const glm::dvec3 eye =
                    target_point + glm::dvec3(1.0, 1.0, 3.0 * span + root.max_height);
                double near_m, far_m;
                renderer.clipPlanesFor(eye, near_m, far_m);
                const lod::Camera cam(eye, target_point, 20.0, vp, near_m, far_m);
                render::RenderSettings settings;
                settings.scheme = scheme;
                settings.epsilon_px = 1.0;
                target.bind();
                renderer.draw(cam, settings);
                const PixelCounts c = classify(renderer, cam, target.readDepth(), validity);
                outside += c.outside;
                outside_drawn += c.outside_drawn;
                inside += c.inside;
                inside_missing += c.inside_missing;
            }
            std::printf("[%s] %s: %zu of %zu pixels over nodata drawn, %zu of %zu over drawable "
                        "cells missing\n",
                        scheme.c_str(), path == &kept ? "kept" : "all", outside_drawn, outside,
                        inside_missing, inside);
            EXPECT_GT(outside, 2000u) << scheme << ": the cameras must see the collar";
            EXPECT_GT(inside, 50000u) << scheme << ": and the footprint";
            EXPECT_EQ(inside_missing, 0u) << scheme << ": a hole inside the footprint";
            if (path == &kept)
                EXPECT_EQ(outside_drawn, 0u) << scheme << ": nodata drawn";
            else
                EXPECT_GT(outside_drawn, 1000u) << scheme << ": the filled collar must be drawn";
        }
    }
}
