#pragma once
// The CPU half of rendering a frame, as TerrainRenderer does it before any GL call, for the
// fuzz targets: the terrain frame the renderer picks by default (a plane, or the WGS 84
// ellipsoid for a raster that goes round the Earth), patch quadtree from the index, ground height,
// clip planes and default camera from the root patch (lod::CoarseTerrain), LOD selection, slot
// residency with the root pinned, synchronous patch loading, the streaming cover (missing patches
// drawn by resident ancestors), Ulrich's chunk meshes and the instance records of the draw; and
// scheme rings' own selection (lod::RingsSelector: updateRings, its streaming cover).
//
// Properties checked (a failure traps, so libFuzzer reports it): every selected patch exists,
// the ε met is at least the one asked for, the cover holds only resident patches and every
// instance record names a slot of the residency.
#include "patch_instances.h"

#include "ridge/archive/archive_reader.h"
#include "ridge/core/error.h"
#include "ridge/lod/archive_frame.h"
#include "ridge/lod/chunk_mesh.h"
#include "ridge/lod/clipmap_selector.h"
#include "ridge/lod/coarse_terrain.h"
#include "ridge/lod/patch_quadtree.h"
#include "ridge/lod/patch_residency.h"
#include "ridge/lod/resident_cover.h"
#include "ridge/lod/rings.h"
#include "ridge/stream/patch_loader.h"

#include <glm/geometric.hpp>

#include <cstdlib>
#include <map>
#include <memory>
#include <utility>
#include <vector>

namespace ridge::fuzz {

inline void require(bool property)
{
    if (!property)
        __builtin_trap();
}

// Everything one archive needs across frames: the renderer's long-lived CPU state.
struct CpuRenderer {
    static constexpr int kSlots = 48;

    const archive::ArchiveReader& reader;
    lod::PatchQuadtree tree;
    stream::PatchLoader loader;
    lod::PatchResidency residency;
    lod::CoarseTerrain coarse;
    uint64_t frame = 0;

    explicit CpuRenderer(const archive::ArchiveReader& r)
        : reader(r), tree(lod::PatchQuadtree::fromArchive(
                         r, lod::terrainFrameOf(r, lod::FrameChoice::Auto, r.path()))),
          loader(r, 64), residency(r.geometry(), kSlots),
          coarse(tree.frame(), tree.bounds(PatchId{0, 0, 0}).min_height,
                 tree.bounds(PatchId{0, 0, 0}).max_height, loader.load(PatchId{0, 0, 0})->codes,
                 r.quantization())
    {
    }

    // One frame: select, make resident (loading synchronously), cover, instance records.
    // Throws ridge::Error where the renderer would (a corrupt patch, a camera it refuses).
    void drawFrame(const lod::Camera& camera, const lod::SelectionSettings& settings)
    {
        const lod::Selection selection = tree.select(camera, settings);
        require(selection.epsilon_px >= settings.epsilon_px);
        std::vector<PatchId> needed{PatchId{0, 0, 0}}; // pinned, as when streaming
        for (const lod::SelectedPatch& s : selection.patches) {
            require(reader.geometry().exists(s.id));
            if (needed.size() < size_t(kSlots))
                needed.push_back(s.id);
        }
        for (const lod::PatchResidency::Load& l : residency.update(needed, ++frame)) {
            try {
                const auto patch = loader.load(l.id);
                if (l.id.level > 0 && patch->codes.size() == size_t(reader.geometry().patchSize()) *
                                                                 reader.geometry().patchSize())
                    (void)lod::buildChunkMesh(patch->codes.data(), reader.geometry().patchSize(),
                                              0.5 * reader.record(l.id).err /
                                                  reader.quantization().scale,
                                              reader.geometry().coveredCellsX(l.id),
                                              reader.geometry().coveredCellsY(l.id));
            } catch (const Error&) {
                residency.release(l.id); // drawn by an ancestor, as a failed stream
            }
        }
        auto resident = [&](PatchId p) { return residency.slotOf(p) >= 0; };
        const lod::ResidentCover cover = lod::residentCover(selection, reader.geometry(), resident);
        lod::Selection drawn;
        drawn.patches = cover.patches;
        for (const lod::SelectedPatch& s : drawn.patches)
            require(resident(s.id));
        const render::PatchInstances instances = render::buildPatchInstances(
            tree, drawn, camera.position(), [&](PatchId p) { return residency.slotOf(p); },
            [&](PatchId p) {
                const lod::PatchBounds& b = tree.bounds(p);
                return double(b.max_height) - double(b.min_height);
            },
            0.01);
        require(instances.total() == drawn.patches.size());
        for (const render::GpuPatchInstance& r : instances.records)
            require(r.layer >= 0 && r.layer < kSlots);
    }

    // A scheme's wanted patches made resident, the root first, as many as the slots take
    // (each must exist in the archive).
    void makeResident(const lod::Selection& desired)
    {
        std::vector<PatchId> needed{PatchId{0, 0, 0}};
        for (const lod::SelectedPatch& s : desired.patches) {
            require(reader.geometry().exists(s.id));
            if (needed.size() < size_t(kSlots))
                needed.push_back(s.id);
        }
        residency.update(needed, ++frame);
    }

    // Scheme rings' selection with `rings` settings (refused when the archive's patches
    // cannot make its grids): select, make resident what fits, cover. Properties: the cover
    // draws only resident patches, touching tiles differ by at most one level and every
    // stitched tile's coarser patch is resident.
    void drawRingsFrame(const lod::Camera& camera, const lod::SelectionSettings& settings,
                        const lod::RingsSettings& rings)
    {
        auto& selector = ring_selectors[{rings.rings, rings.vertex_step}];
        if (!selector)
            selector = std::make_unique<lod::RingsSelector>(tree, rings); // may throw Error
        lod::Selection desired;
        selector->select(camera, settings, desired);
        require(desired.patches.size() <= settings.max_patches || desired.patches.size() == 1);
        makeResident(desired);
        auto resident = [&](PatchId p) { return residency.slotOf(p) >= 0; };
        lod::ResidentCover cover;
        selector->cover(desired, resident, cover);
        for (const lod::SelectedPatch& s : cover.patches)
            require(resident(s.id));
        std::map<std::pair<int, int>, int> level;
        for (const lod::RingTile& t : selector->drawnTiles()) {
            require(resident(selector->ancestorOf(t.x, t.y, t.level)));
            require(!t.stitch || resident(selector->ancestorOf(t.x, t.y, t.level - 1)));
            level[{t.x, t.y}] = t.level;
        }
        for (const auto& [at, l] : level)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    auto it = level.find({at.first + dx, at.second + dy});
                    require(it == level.end() || std::abs(it->second - l) <= 1);
                }
    }
    std::map<std::pair<int, int>, std::unique_ptr<lod::RingsSelector>> ring_selectors;

    // Scheme clipmaps' policy: the level windows placed, the pending writes drained for what is
    // resident. Every write lies in its level's window (the GL half addresses its texels
    // modulo the window's texture: a write outside would overwrite a live sample), reads the
    // patch the policy names for each of its corners, and nothing is drawn that is not
    // complete.
    void drawClipmapsFrame(const lod::Camera& camera, const lod::SelectionSettings& settings,
                           const lod::ClipmapSettings& clipmap)
    {
        auto& selector = clipmap_selectors[{clipmap.n, clipmap.levels}];
        if (!selector)
            selector = std::make_unique<lod::ClipmapSelector>(tree, clipmap); // may throw Error
        lod::Selection desired;
        selector->select(camera, settings, desired);
        require(desired.patches.size() <= settings.max_patches);
        makeResident(desired);
        auto resident = [&](PatchId p) { return residency.slotOf(p) >= 0; };
        std::vector<lod::ClipmapWrite> writes;
        selector->takeWrites(resident, writes);
        const lod::ClipmapWindows& w = selector->windows();
        for (const lod::ClipmapWrite& wr : writes) {
            require(resident(wr.patch) && wr.level >= 0 && wr.level < w.levelCount());
            const lod::LevelRect window = w.level(wr.level).window(w.n());
            require(wr.rect.area() > 0 && wr.rect.x0 >= window.x0 && wr.rect.x1 <= window.x1 &&
                    wr.rect.y0 >= window.y0 && wr.rect.y1 <= window.y1);
            require(selector->patchOf(wr.level, wr.rect.x0, wr.rect.y0) == wr.patch);
            require(selector->patchOf(wr.level, wr.rect.x1 - 1, wr.rect.y1 - 1) == wr.patch);
        }
        require(selector->finestDrawn() <= selector->finestWanted());
        for (int k = 0; k <= selector->finestDrawn(); ++k)
            require(selector->complete(k));
    }
    std::map<std::pair<int, int>, std::unique_ptr<lod::ClipmapSelector>> clipmap_selectors;

    // The views a user reaches first: the default camera, straight down over the centre, low
    // over the south-west corner looking across, and far above.
    std::vector<lod::Camera> typicalCameras(lod::Viewport viewport) const
    {
        std::vector<lod::Camera> cameras{coarse.defaultCamera(viewport)};
        const lod::Box box = coarse.box();
        const glm::dvec3 centre = box.centre();
        const double size = glm::length(box.max - box.min) + 1.0;
        const glm::dvec3 corner(box.min.x, box.min.y, coarse.groundHeight(box.min.x, box.min.y));
        const std::pair<glm::dvec3, glm::dvec3> views[] = {
            {centre + glm::dvec3(1.0, 0.5, size), centre},
            {corner + glm::dvec3(0.0, 0.0, 20.0), centre},
            {centre + glm::dvec3(0.0, -size * 20.0, size * 10.0), centre},
        };
        for (const auto& [position, look_at] : views) {
            double near_m = 1.0, far_m = 1e6;
            coarse.clipPlanesFor(position, near_m, far_m);
            cameras.emplace_back(position, look_at, 60.0, viewport, near_m, far_m);
        }
        return cameras;
    }
};

// A few frames of every typical camera at several ε, culling on and off.
inline void runCpuFrames(const archive::ArchiveReader& reader)
{
    CpuRenderer renderer(reader);
    for (const lod::Camera& camera : renderer.typicalCameras({320, 200})) {
        for (double epsilon : {0.5, 2.0, 24.0}) {
            lod::SelectionSettings settings;
            settings.epsilon_px = epsilon;
            settings.cull = epsilon != 24.0;
            settings.max_patches = CpuRenderer::kSlots - 1;
            try {
                renderer.drawFrame(camera, settings);
            } catch (const Error&) {
            }
            try {
                renderer.drawRingsFrame(camera, settings, lod::RingsSettings{});
            } catch (const Error&) {
            }
            try {
                renderer.drawClipmapsFrame(camera, settings, lod::ClipmapSettings{});
            } catch (const Error&) {
            }
        }
    }
}

} // namespace ridge::fuzz
