#include "ridge/lod/patch_quadtree.h"

#include "ridge/archive/archive_reader.h"
#include "ridge/core/error.h"
#include "ridge/lod/screen_space_error.h"

#include <algorithm>
#include <cmath>

namespace ridge::lod {

PatchQuadtree::PatchQuadtree(TerrainFrame frame, std::vector<PatchBounds> bounds)
    : frame_(std::move(frame)), bounds_(std::move(bounds))
{
    if (int64_t(bounds_.size()) != geometry().patchCount())
        throw Error("patch quadtree: bounds for " + std::to_string(bounds_.size()) +
                    " patches, the geometry has " + std::to_string(geometry().patchCount()));
}

PatchQuadtree PatchQuadtree::fromArchive(const archive::ArchiveReader& reader)
{
    const archive::Header& h = reader.header();
    return fromArchive(reader, TerrainFrame(reader.geometry(), h.spacing_x, h.spacing_y));
}

PatchQuadtree PatchQuadtree::fromArchive(const archive::ArchiveReader& reader, TerrainFrame frame)
{
    std::vector<PatchBounds> bounds;
    bounds.reserve(reader.index().size());
    for (const archive::PatchRecord& r : reader.index())
        bounds.push_back({r.min_height, r.max_height, r.err});
    return PatchQuadtree(std::move(frame), std::move(bounds));
}

Box PatchQuadtree::box(PatchId p, double exaggeration) const
{
    const PatchBounds& b = bounds(p);
    if (exaggeration == 1.0)
        return frame_.patchBox(p, b.min_height, b.max_height);
    return frame_.patchBox(p, exaggeration * b.min_height, exaggeration * b.max_height);
}

void SelectionSettings::validate() const
{
    checkParameter("epsilon_px", epsilon_px, kEpsilonPxRange);
    checkParameter("error_scale", error_scale, kErrorScaleRange);
    checkParameter("texel_px", texel_px, kTexelPxRange);
    checkParameter("exaggeration", exaggeration, kExaggerationRange);
    checkParameter("straight_cells", straight_cells, kStraightCellsRange);
    if (max_patches < 1)
        throw Error("max_patches is 0: must be at least 1 (the root alone always fits)");
}

Selection PatchQuadtree::select(const Camera& camera, const SelectionSettings& settings) const
{
    settings.validate();
    const Frustum frustum(camera);
    // Behind the Earth (a globe frame covering it; inactive otherwise).
    const HorizonOccluder horizon(frame_, camera.position(),
                                  settings.exaggeration * double(bounds({0, 0, 0}).min_height));
    const HorizonOccluder* occluder = settings.cull && horizon.active() ? &horizon : nullptr;
    const double gamma = screenSpaceErrorFactor(camera);
    double epsilon = settings.epsilon_px, texel = settings.texel_px;
    for (;;) {
        Selection s;
        s.epsilon_px = epsilon;
        s.texel_px = texel;
        // Err_Scr is linear in Err(P): scaling γ scales every patch's error (the chunks'
        // simplification, the exaggerated heights).
        visit(PatchId{0, 0, 0}, camera, settings.cull ? &frustum : nullptr, occluder,
              {gamma, gamma * settings.error_scale * settings.exaggeration, settings.exaggeration,
               epsilon, texel},
              settings, s);
        // At ε = ∞ every visible patch with a finite Err_Scr stops at the root; should a NaN
        // bound (a corrupt index) still refine, give up raising rather than loop forever.
        if (s.patches.size() <= settings.max_patches || std::isinf(epsilon))
            return s;
        epsilon = std::max(epsilon * 1.25, 1e-3); // from ε = 0 (brute force) too
        texel *= 1.25;                            // stays 0 when off
    }
}

void PatchQuadtree::visit(PatchId p, const Camera& camera, const Frustum* frustum,
                          const HorizonOccluder* horizon, const Thresholds& t,
                          const SelectionSettings& settings, Selection& out) const
{
    ++out.visited;
    const Box b = box(p, t.exaggeration);
    Visibility visibility = Visibility::Inside;
    if (frustum) {
        visibility = frustum->classify(b);
        if (visibility == Visibility::Outside) {
            ++out.culled;
            return;
        }
    }
    if (horizon && horizon->hides(b)) {
        ++out.culled;
        return;
    }
    const double rho = distanceToBox(camera.position(), b);
    const double depth =
        settings.conservative_distance ? visibleDepthBound(camera, b, rho, settings.side_on) : rho;
    // On a globe the patch's straight cells also pass below the curved surface (0 on a plane).
    const double err = double(bounds(p).err) +
                       frame_.chordSag(settings.straight_cells * double(geometry().step(p.level))) /
                           t.exaggeration;
    const double err_scr = screen_space_error(t.error_gamma, err, depth);
    // The level's sample spacing, the coarser of the two axes.
    const double spacing =
        double(geometry().step(p.level)) * std::max(frame_.spacingX(), frame_.spacingY());
    const double texel_scr = projectedSampleSpacing(t.gamma, spacing, depth);
    const bool texels_fine = t.texel <= 0.0 || texel_scr <= t.texel;
    if (p.level == geometry().finestLevel() || (err_scr <= t.epsilon && texels_fine)) {
        out.patches.push_back({p, err_scr, visibility, texel_scr, err_scr});
        return;
    }
    for (int k = 0; k < 4; ++k) {
        const PatchId child{p.level + 1, 2 * p.x + (k & 1), 2 * p.y + (k >> 1)};
        if (geometry().exists(child))
            visit(child, camera, frustum, horizon, t, settings, out);
    }
}

} // namespace ridge::lod
