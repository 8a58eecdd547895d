#pragma once
// The terrain's east and south borders, where a coarse level's samples do not land on the
// last column or row: the surface must still reach it (no strip left without surface), and a
// scheme's patches must stay closed there — including flat patches whose skirts hang only the
// rounding margin. The checks the schemes' own tests run (tests/render/schemes/).
#include "terrain_renderer_fixture.h"

#include "ridge/io/raster_source.h"
#include "ridge/io/raster_writer.h"
#include "ridge/pipeline/build.h"
#include "ridge/pipeline/level_decoder.h"
#include "ridge/render/terrain_renderer.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace ridge::test {

// A synchronous renderer over `path` for one scheme spec (RendererOptions::schemes).
inline Scene openScene(const std::string& path, const std::string& spec)
{
    Scene s;
    s.reader = std::make_unique<archive::ArchiveReader>(path);
    render::RendererOptions ro;
    ro.synchronous_stats = true;
    ro.schemes = {spec};
    ro.max_resident_patches = 1024;
    s.renderer = std::make_unique<render::TerrainRenderer>(*s.reader, ro);
    s.finest = toMetres(decodeLevel(*s.reader, s.reader->geometry().finestLevel()),
                        s.reader->quantization());
    return s;
}

// A drawn patch of a level whose samples miss the last column (row): the strip between its
// last sample inside the extent and the border is what the checks below are about.
inline bool drawsShortLevelOnBorder(const render::CapturedSurface& s, const PyramidGeometry& g)
{
    for (const PatchId& p : s.patches) {
        const int64_t step = g.step(p.level), span = int64_t(g.cells()) * step;
        const bool east = (p.x + 1) * span > g.width() - 1 && (g.width() - 1) % step != 0;
        const bool south = (p.y + 1) * span > g.height() - 1 && (g.height() - 1) % step != 0;
        if (east || south)
            return true;
    }
    return false;
}

struct BorderCamera {
    std::string name;
    lod::Camera camera;
    double epsilon_px;
};

// High above the whole terrain (only the coarsest levels), and low outside the east and the
// south border looking back across it.
inline std::vector<BorderCamera> borderCameras(const render::TerrainRenderer& r)
{
    const lod::TerrainFrame& f = r.quadtree().frame();
    const lod::PatchBounds& root = r.quadtree().bounds({0, 0, 0});
    const lod::Viewport vp{480, 270};
    const double w = f.extentX(), h = f.extentY(), top = root.max_height;
    auto camera = [&](glm::dvec3 pos, glm::dvec3 at) {
        double near_m, far_m;
        r.clipPlanesFor(pos, near_m, far_m);
        return lod::Camera(pos, at, 60.0, vp, near_m, far_m);
    };
    const glm::dvec3 centre(0.5 * w, 0.5 * h, root.min_height);
    const double east_x = f.xOf(f.geometry().width() - 1),
                 south_y = f.yOf(f.geometry().height() - 1);
    return {
        {"high, root only", camera(centre + glm::dvec3(0.1 * w, -0.2 * h, 2.5 * w + top), centre),
         1000.0},
        {"high, coarse", camera(centre + glm::dvec3(0.3 * w, 0.2 * h, 1.5 * w + top), centre), 8.0},
        {"outside the east border",
         camera({east_x + 0.4 * w, 0.4 * h, top + 0.1 * w},
                {east_x - 0.1 * w, 0.5 * h, root.min_height}),
         2.0},
        {"outside the east border, far",
         camera({east_x + 1.5 * w, 0.6 * h, top + 0.4 * w}, {east_x, 0.5 * h, root.min_height}),
         4.0},
        {"outside the south border",
         camera({0.5 * w, south_y - 0.4 * h, top + 0.1 * w},
                {0.4 * w, south_y + 0.1 * h, root.min_height}),
         2.0},
        {"outside the south-east corner, far",
         camera({east_x + w, south_y - h, top + 0.5 * w}, {east_x, south_y, root.min_height}), 4.0},
    };
}

struct Counts {
    size_t open_edges = 0, uncovered = 0, short_borders = 0;
};

// Every camera through every check; returns the totals for the report and the failure test.
inline Counts checkBorders(Scene& s, const std::string& what, double texel_px = 0.0)
{
    Counts total;
    const lod::TerrainFrame& frame = s.renderer->quadtree().frame();
    for (const BorderCamera& c : borderCameras(*s.renderer)) {
        render::RenderSettings settings;
        settings.scheme = s.renderer->schemes().front();
        settings.epsilon_px = c.epsilon_px;
        // The levels ε selects at these cameras (root only, coarse) are what the border checks
        // are about; the texture-detail criterion would refine them away (0 unless asked).
        settings.texel_px = texel_px;
        settings.cull_blocks = false; // whole patches: culled blocks would open edges
        const render::CapturedSurface surface = s.renderer->capture(c.camera, settings);
        const test::WatertightReport w = test::checkWatertight(surface, frame);
        const test::ScreenErrorReport e =
            test::measureScreenSpaceError(surface, frame, s.finest, c.camera);
        EXPECT_GT(e.samples, 1000u) << what << ", " << c.name << ": the terrain must be in view";
        EXPECT_EQ(w.open_edges, 0u) << what << ", " << c.name << ": " << w.first_problem;
        EXPECT_EQ(w.overused_edges, 0u) << what << ", " << c.name;
        EXPECT_EQ(w.uncovered_seams, 0u) << what << ", " << c.name << ": " << w.first_problem;
        EXPECT_EQ(e.uncovered, 0u) << what << ", " << c.name;
        total.open_edges += w.open_edges;
        total.uncovered += e.uncovered;
        total.short_borders += drawsShortLevelOnBorder(surface, frame.geometry());
        std::printf("%s, %s: %zu patches, %zu open edges, %zu uncovered of %zu samples, %.3f px\n",
                    what.c_str(), c.name.c_str(), surface.patches.size(), w.open_edges, e.uncovered,
                    e.samples, e.max_px);
    }
    return total;
}

// Everest with its eastern 45 % replaced by a sea at height 0, with 1 km spacing and patches
// of 33, built once into `scratch`: those patches have Err(P) = 0 and exact chunks, so their
// skirts hang only the rounding margin (a centimetre), under cells of kilometres (steps up to
// 16) — thin walls the clipping shader must keep.
inline std::string seaArchive(ScratchDir& scratch)
{
    const std::string archive = scratch.path("everest_sea.ridge");
    if (std::filesystem::exists(archive))
        return archive;
    const io::ElevationRaster everest = io::ingestRaster(test::dataPath("everest_crop.tif"));
    const int W = everest.grid.width, H = everest.grid.height;
    std::vector<float> metres(size_t(W) * H);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
            metres[size_t(y) * W + x] =
                x >= W * 55 / 100 ? 0.f
                                  : float(everest.quantization.toMetres(everest.grid.at(x, y)));
    const std::string tif = scratch.path("everest_sea.tif");
    io::writeGeoTiff(tif, metres.data(), W, H, io::GeoReference{});
    BuildOptions options;
    options.patch_size = 33;
    options.progress = {};
    options.ingest.spacing = 1000.0;
    buildArchive(tif, archive, options);
    return archive;
}

} // namespace ridge::test
