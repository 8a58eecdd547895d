#pragma once
// The fixture of the renderer's tests on SRTM Everest (terrain_renderer_test.cpp and the
// schemes' own tests, tests/render/schemes/): archives, renderers over them, cameras.
#include "captured_surface_checks.h"
#include "fixture_archives.h"

#include "ridge/core/sanitizer.h"
#include "ridge/gpu/context.h"
#include "ridge/pipeline/build.h"
#include "ridge/pipeline/level_decoder.h"
#include "ridge/render/terrain_renderer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

namespace ridge::test {

// Built with AddressSanitizer: sweeps take fewer cameras.
constexpr bool kSanitized = RIDGE_ADDRESS_SANITIZER != 0;

struct Scene {
    std::unique_ptr<archive::ArchiveReader> reader;
    std::unique_ptr<render::TerrainRenderer> renderer;
    std::vector<float> finest; // metres, full resolution
};

class TerrainRendererTest : public ::testing::Test {
  protected:
    static void SetUpTestSuite()
    {
        scratch_ = new test::ScratchDir();
        context_ = gpu::HeadlessContext::create().release();
        std::printf("GL renderer: %s (%s)\n", context_->rendererName().c_str(),
                    context_->platformName().c_str());
    }
    static void TearDownTestSuite()
    {
        delete context_;
        delete scratch_;
    }

    // Patches of 33 samples give the Everest crop 5 levels: an unbalanced tree and seams
    // between patches up to 4 levels apart.
    // `schemes`: the renderer's (RendererOptions::schemes specs; default every registered
    // scheme with its default options, whatever it needs).
    static Scene scene(const std::string& codec, double max_error = 0.0,
                       const std::vector<std::string>& schemes = render::lodSchemeNames())
    {
        return sceneOf(test::buildEverestArchive(*scratch_, codec, 33, max_error), schemes);
    }

    // The Everest crop with patches of `patch_size` and its heights scaled by `z_scale` (0.05:
    // a low-relief terrain of 170..440 m, slopes of a few degrees).
    static Scene scene(const std::string& codec, double max_error, int patch_size, double z_scale)
    {
        BuildOptions options;
        options.patch_size = patch_size;
        options.codec = codec;
        if (codec == "progressive")
            options.max_error = max_error;
        options.ingest.z_scale = z_scale;
        options.progress = {};
        const std::string path = scratch_->path(codec + "_" + std::to_string(patch_size) + "_z" +
                                                std::to_string(z_scale) + ".ridge");
        buildArchive(test::dataPath("everest_crop.tif"), path, options);
        return sceneOf(path, render::lodSchemeNames());
    }

    static Scene sceneOf(const std::string& path, const std::vector<std::string>& schemes)
    {
        Scene s;
        s.reader = std::make_unique<archive::ArchiveReader>(path);
        render::RendererOptions ro;
        ro.synchronous_stats = true;
        ro.schemes = schemes;
        ro.max_resident_patches = 1024;
        s.renderer = std::make_unique<render::TerrainRenderer>(*s.reader, ro);
        // Full resolution: the archive's finest level as decoded (for the lossless codec the
        // source itself; the lossy codec's own bound against the source is verify's job).
        s.finest = toMetres(decodeLevel(*s.reader, s.reader->geometry().finestLevel()),
                            s.reader->quantization());
        return s;
    }

    // Cameras over and around the terrain, looking at random points of it, low and high.
    static std::vector<lod::Camera> randomCameras(const render::TerrainRenderer& r, int count,
                                                  lod::Viewport vp, unsigned seed)
    {
        const lod::TerrainFrame& f = r.quadtree().frame();
        std::mt19937 rng(seed);
        std::uniform_real_distribution<double> u(0.0, 1.0);
        std::vector<lod::Camera> cameras;
        while (int(cameras.size()) < count) {
            const double x = (u(rng) * 1.4 - 0.2) * f.extentX(),
                         y = (u(rng) * 1.4 - 0.2) * f.extentY();
            const double above = 30.0 * std::pow(400.0, u(rng)); // 30 m .. 12 km above ground
            const glm::dvec3 pos(x, y, r.groundHeight(x, y) + above);
            const double tx = u(rng) * f.extentX(), ty = u(rng) * f.extentY();
            const glm::dvec3 at(tx, ty, r.groundHeight(tx, ty));
            if (glm::length(at - pos) < 1.0)
                continue;
            double near_m, far_m;
            r.clipPlanesFor(pos, near_m, far_m);
            cameras.emplace_back(pos, at, 40.0 + 40.0 * u(rng), vp, near_m, far_m);
        }
        return cameras;
    }

    // Cameras 15..200 m above the ground looking across it 300 m..3 km ahead, half of them
    // up or down the steepest of a few candidate slopes: where blocks near the camera project
    // largest and the view grazes the relief.
    static std::vector<lod::Camera> lowCameras(const render::TerrainRenderer& r, int count,
                                               lod::Viewport vp, unsigned seed)
    {
        const lod::TerrainFrame& f = r.quadtree().frame();
        std::mt19937 rng(seed);
        std::uniform_real_distribution<double> u(0.0, 1.0);
        std::vector<lod::Camera> cameras;
        const double pi = 3.14159265358979;
        while (int(cameras.size()) < count) {
            const bool slope = cameras.size() % 2 == 1;
            double x = 0, y = 0, heading = 2 * pi * u(rng), steepest = -1;
            for (int k = 0; k < (slope ? 12 : 1); ++k) {
                const double cx = (0.1 + 0.8 * u(rng)) * f.extentX(),
                             cy = (0.1 + 0.8 * u(rng)) * f.extentY(), h = 2 * f.spacingX();
                const double gx = r.groundHeight(cx + h, cy) - r.groundHeight(cx - h, cy),
                             gy = r.groundHeight(cx, cy + h) - r.groundHeight(cx, cy - h);
                if (std::hypot(gx, gy) > steepest) {
                    steepest = std::hypot(gx, gy);
                    x = cx;
                    y = cy;
                    // Up the slope, or down it.
                    if (slope)
                        heading = std::atan2(gy, gx) + (u(rng) < 0.5 ? 0.0 : pi);
                }
            }
            const double above = 15.0 * std::pow(200.0 / 15.0, u(rng));
            const glm::dvec3 pos(x, y, r.groundHeight(x, y) + above);
            const double ahead = 300.0 * std::pow(10.0, u(rng));
            const double tx = x + ahead * std::cos(heading), ty = y + ahead * std::sin(heading);
            const glm::dvec3 at(tx, ty, r.groundHeight(tx, ty));
            double near_m, far_m;
            r.clipPlanesFor(pos, near_m, far_m);
            cameras.emplace_back(pos, at, 40.0 + 40.0 * u(rng), vp, near_m, far_m);
        }
        return cameras;
    }

    // Eight random cameras' captures of `scheme` at ε = `epsilon_px` (texture detail off, whole
    // patches): each must be watertight with skirts and cover every finest sample. Returns the
    // largest projected error over them and adds the patches drawn to `patches`.
    static double worstErrorOverRandomCameras(const Scene& s, const std::string& scheme,
                                              double epsilon_px, const std::string& name,
                                              size_t& patches)
    {
        const auto cameras = randomCameras(*s.renderer, 8, {480, 270}, 31);
        double worst = 0.0;
        for (size_t k = 0; k < cameras.size(); ++k) {
            render::RenderSettings settings;
            settings.scheme = scheme;
            settings.epsilon_px = epsilon_px;
            settings.texel_px = 0.0; // how close to ε the mesh comes: ε alone decides
            settings.cull_blocks = false;
            const render::CapturedSurface surface = s.renderer->capture(cameras[k], settings);
            patches += surface.patches.size();
            const test::WatertightReport w =
                test::checkWatertight(surface, s.renderer->quadtree().frame());
            EXPECT_GT(w.skirt_triangles, 0u);
            EXPECT_EQ(w.open_edges, 0u) << name << " camera " << k << ": " << w.first_problem;
            EXPECT_EQ(w.overused_edges, 0u) << name << " camera " << k;
            EXPECT_EQ(w.uncovered_seams, 0u) << name << " camera " << k << ": " << w.first_problem;
            const test::ScreenErrorReport e = test::measureScreenSpaceError(
                surface, s.renderer->quadtree().frame(), s.finest, cameras[k]);
            EXPECT_EQ(e.uncovered, 0u);
            worst = std::max(worst, e.max_px);
        }
        std::printf("%s: max projected error %.3f px at ε = %g\n", name.c_str(), worst, epsilon_px);
        return worst;
    }

    // Surface vertices of `surface` that lie on a sample of their patch's level (within a
    // millimetre across): how many, and how many of those are off that sample's decoded height
    // by more than `tolerance_m` (float camera-relative vertices: a centimetre). What a
    // scheme that draws each level's grid of samples as its vertices promises; vertices off
    // the grid (clipped at the valid extent) are not counted.
    struct GridVertices {
        size_t on_grid = 0, off_height = 0, all = 0;
    };
    static GridVertices gridVertices(const Scene& s, const render::CapturedSurface& surface,
                                     double tolerance_m = 0.01)
    {
        const PyramidGeometry& g = s.reader->geometry();
        const lod::TerrainFrame& f = s.renderer->quadtree().frame();
        std::map<int, std::vector<float>> heights; // per level, decoded, metres
        GridVertices out;
        for (const render::CapturedVertex& v : surface.vertices) {
            if (v.skirt != 0)
                continue;
            ++out.all;
            const int level = surface.patches[size_t(v.instance)].level;
            const int64_t step = g.step(level);
            const double x = surface.camera_position.x + v.x, y = surface.camera_position.y + v.y;
            const double column = x / f.spacingX() / double(step),
                         row = (double(g.height() - 1) - y / f.spacingY()) / double(step);
            const double i = std::round(column), j = std::round(row);
            if (std::abs(column - i) * step * f.spacingX() > 1e-3 ||
                std::abs(row - j) * step * f.spacingY() > 1e-3)
                continue;
            auto [it, added] = heights.try_emplace(level);
            if (added)
                it->second = toMetres(decodeLevel(*s.reader, level), s.reader->quantization());
            const int width = g.validLevelWidth(level);
            if (i < 0 || j < 0 || i >= width || size_t(j) * width + size_t(i) >= it->second.size())
                continue;
            ++out.on_grid;
            const double z = surface.camera_position.z + v.z;
            out.off_height += std::abs(z - it->second[size_t(j) * width + size_t(i)]) > tolerance_m;
        }
        return out;
    }

    inline static test::ScratchDir* scratch_ = nullptr;
    inline static gpu::HeadlessContext* context_ = nullptr;
};

} // namespace ridge::test
