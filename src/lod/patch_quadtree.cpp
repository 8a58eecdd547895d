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
    const Frustum* culling = settings.cull ? &frustum : nullptr;
    const double gamma = screenSpaceErrorFactor(camera);
    // Err_Scr is linear in Err(P): scaling γ scales every patch's error (the chunks'
    // simplification, the exaggerated heights).
    Thresholds t{gamma, gamma * settings.error_scale * settings.exaggeration, settings.exaggeration,
                 settings.epsilon_px, settings.texel_px};
    Selection s;
    for (;;) {
        s.patches.clear();
        s.visited = s.culled = 0;
        visit(PatchId{0, 0, 0}, camera, culling, occluder, t, settings, s);
        // At ε = ∞ every visible patch with a finite Err_Scr stops at the root; should a NaN
        // bound (a corrupt index) still refine, give up raising rather than loop forever.
        if (s.patches.size() <= settings.max_patches || std::isinf(t.epsilon))
            break;
        t.epsilon = std::max(t.epsilon * 1.25, 1e-3); // from ε = 0 (brute force) too
    }
    s.epsilon_px = t.epsilon;
    // Texture detail in what the drawn patches leave of max_patches; with none left (or a
    // target so coarse that every drawn patch's own texels meet it) there is none.
    while (t.texel > 0.0) {
        s.detail.clear();
        for (const SelectedPatch& d : s.patches)
            if (d.id.level < geometry().finestLevel() && d.texel_spacing > t.texel)
                visitDetail(d.id, {false, d.visibility, d.screen_error, d.texel_spacing}, 0, camera,
                            culling, occluder, t, settings, s);
        if (s.detail.empty() || s.patches.size() + s.detail.size() <= settings.max_patches)
            break;
        t.texel *= 1.25;
    }
    s.texel_px = t.texel;
    return s;
}

PatchQuadtree::Measured PatchQuadtree::measure(PatchId p, const Camera& camera,
                                               const Frustum* frustum,
                                               const HorizonOccluder* horizon, const Thresholds& t,
                                               const SelectionSettings& settings) const
{
    Measured m;
    const Box b = box(p, t.exaggeration);
    if (frustum) {
        m.visibility = frustum->classify(b);
        if (m.visibility == Visibility::Outside)
            return {true};
    }
    if (horizon && horizon->hides(b))
        return {true};
    const double rho = distanceToBox(camera.position(), b);
    const double depth =
        settings.conservative_distance ? visibleDepthBound(camera, b, rho, settings.side_on) : rho;
    // On a globe the patch's straight cells also pass below the curved surface (0 on a plane).
    const double err = double(bounds(p).err) +
                       frame_.chordSag(settings.straight_cells * double(geometry().step(p.level))) /
                           t.exaggeration;
    m.err_scr = screen_space_error(t.error_gamma, err, depth);
    // The level's sample spacing, the coarser of the two axes.
    const double spacing =
        double(geometry().step(p.level)) * std::max(frame_.spacingX(), frame_.spacingY());
    m.texel_scr = projectedSampleSpacing(t.gamma, spacing, depth);
    return m;
}

void PatchQuadtree::visit(PatchId p, const Camera& camera, const Frustum* frustum,
                          const HorizonOccluder* horizon, const Thresholds& t,
                          const SelectionSettings& settings, Selection& out) const
{
    ++out.visited;
    const Measured m = measure(p, camera, frustum, horizon, t, settings);
    if (m.culled) {
        ++out.culled;
        return;
    }
    if (p.level == geometry().finestLevel() || m.err_scr <= t.epsilon) {
        out.patches.push_back({p, m.err_scr, m.visibility, m.texel_scr, m.err_scr});
        return;
    }
    for (int k = 0; k < 4; ++k) {
        const PatchId child{p.level + 1, 2 * p.x + (k & 1), 2 * p.y + (k >> 1)};
        if (geometry().exists(child))
            visit(child, camera, frustum, horizon, t, settings, out);
    }
}

// Children of a patch whose texels are coarser than the target, down to the target, the
// finest level or kShadingDepth below the drawn patch; culled subtrees are left out (not
// seen, not shaded).
void PatchQuadtree::visitDetail(PatchId p, const Measured& m, int depth, const Camera& camera,
                                const Frustum* frustum, const HorizonOccluder* horizon,
                                const Thresholds& t, const SelectionSettings& settings,
                                Selection& out) const
{
    if (depth > 0 &&
        (depth == kShadingDepth || p.level == geometry().finestLevel() || m.texel_scr <= t.texel)) {
        out.detail.push_back({p, m.err_scr, m.visibility, m.texel_scr, m.texel_scr});
        return;
    }
    for (int k = 0; k < 4; ++k) {
        const PatchId child{p.level + 1, 2 * p.x + (k & 1), 2 * p.y + (k >> 1)};
        if (!geometry().exists(child))
            continue;
        const Measured c = measure(child, camera, frustum, horizon, t, settings);
        if (!c.culled)
            visitDetail(child, c, depth + 1, camera, frustum, horizon, t, settings, out);
    }
}

} // namespace ridge::lod
