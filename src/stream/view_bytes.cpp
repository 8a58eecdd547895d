#include "ridge/stream/view_bytes.h"

#include "ridge/archive/archive_reader.h"
#include "ridge/core/error.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace ridge::stream {

lod::SelectionSettings rendererSelectionSettings(double epsilon_px, double texel_px)
{
    // As TerrainRenderer::Impl::prepare fills them for "tess" (its adjustSelection changes
    // nothing), less the slot budget: a cold view is counted whole.
    lod::SelectionSettings s;
    s.epsilon_px = epsilon_px;
    s.texel_px = texel_px;
    s.cull = true;
    s.side_on = true;
    return s;
}

std::vector<PatchId> patchesToFetch(const PyramidGeometry& geometry,
                                    const std::vector<lod::SelectedPatch>& selected,
                                    bool with_ancestors)
{
    // A flag per patch: ancestors shared by many selected patches are met many times, and
    // the walk up stops at the first one already marked (its ancestors are marked too).
    std::vector<char> fetched(size_t(geometry.patchCount()), 0);
    for (const lod::SelectedPatch& s : selected) {
        PatchId p = s.id;
        for (;;) {
            char& flag = fetched[size_t(geometry.patchIndex(p))];
            if (flag)
                break;
            flag = 1;
            if (!with_ancestors || p.level == 0)
                break;
            p = p.parent();
        }
    }
    std::vector<PatchId> out;
    for (size_t i = 0; i < fetched.size(); ++i)
        if (fetched[i])
            out.push_back(geometry.patchAt(int64_t(i)));
    return out;
}

ViewBytes viewBytes(const archive::ArchiveReader& reader, const lod::PatchQuadtree& quadtree,
                    const lod::Camera& camera, const lod::SelectionSettings& settings)
{
    lod::Selection selection = quadtree.select(camera, settings);
    // The drawn patches and their texture detail: the renderer streams both.
    std::vector<lod::SelectedPatch>& wanted = selection.patches;
    wanted.insert(wanted.end(), selection.detail.begin(), selection.detail.end());
    ViewBytes out;
    out.selected = wanted.size();
    out.epsilon_px = selection.epsilon_px;
    out.counts_ancestors = reader.codec().capabilities().needs_ancestors;
    const std::vector<PatchId> fetched =
        patchesToFetch(reader.geometry(), wanted, out.counts_ancestors);
    out.patches = fetched.size();
    for (const PatchId p : fetched)
        out.bytes += reader.record(p).size;
    return out;
}

ViewBytes viewBytes(const archive::ArchiveReader& reader, const lod::Camera& camera,
                    double epsilon_px, double texel_px)
{
    return viewBytes(reader, lod::PatchQuadtree::fromArchive(reader), camera,
                     rendererSelectionSettings(epsilon_px, texel_px));
}

std::string typicalViewName(TypicalView view)
{
    switch (view) {
    case TypicalView::Near:
        return "near";
    case TypicalView::Mid:
        return "mid";
    case TypicalView::Far:
        return "far";
    }
    return "?";
}

namespace {

constexpr double kFovYDegrees = 60.0;

// The max height of the finest patch under terrain-frame point (x, y): an index bound on
// every sample there (PatchRecord::max_height covers the patch and its descendants).
double finestTopAt(const lod::PatchQuadtree& quadtree, double x, double y)
{
    const lod::TerrainFrame& f = quadtree.frame();
    const PyramidGeometry& g = f.geometry();
    const int finest = g.finestLevel();
    const auto clampTo = [](double v, int n) { return std::clamp(int(std::floor(v)), 0, n - 1); };
    const PatchId p{finest, clampTo(f.columnOf(x) / g.cells(), g.patchesX(finest)),
                    clampTo(f.rowOf(y) / g.cells(), g.patchesY(finest))};
    return quadtree.bounds(p).max_height;
}

// Looking at `target` from the south, `elevation_degrees` above the horizontal, `distance`
// away, never lower than `min_z`.
glm::dvec3 fromTheSouth(glm::dvec3 target, double elevation_degrees, double distance, double min_z)
{
    const double a = elevation_degrees * std::numbers::pi / 180.0;
    glm::dvec3 p = target + distance * glm::dvec3(0.0, -std::cos(a), std::sin(a));
    p.z = std::max(p.z, min_z);
    return p;
}

} // namespace

lod::Camera typicalViewCamera(const lod::PatchQuadtree& quadtree, TypicalView view,
                              lod::Viewport viewport)
{
    const lod::TerrainFrame& f = quadtree.frame();
    const lod::PatchBounds& root = quadtree.bounds(PatchId{0, 0, 0});
    const double w = f.extentX(), h = f.extentY();
    const double z0 = root.min_height, z1 = root.max_height;
    const glm::dvec3 centre(0.5 * w, 0.5 * h, 0.5 * (z0 + z1));
    const double radius = 0.5 * std::sqrt(w * w + h * h + (z1 - z0) * (z1 - z0));
    const double above_top = z1 + kNearViewHeightAboveTop;
    glm::dvec3 position, look_at;
    switch (view) {
    case TypicalView::Near: {
        position = {centre.x, centre.y,
                    finestTopAt(quadtree, centre.x, centre.y) + kNearViewHeightAboveTop};
        const double pitch = 5.0 * std::numbers::pi / 180.0;
        look_at = position + glm::dvec3(0.0, std::cos(pitch), -std::sin(pitch));
        break;
    }
    case TypicalView::Mid:
        look_at = centre;
        position = fromTheSouth(centre, 30.0, radius, above_top);
        break;
    case TypicalView::Far:
        look_at = centre;
        position = fromTheSouth(centre, 60.0, 2.0 * radius, above_top);
        break;
    }
    const double far_m = 2.0 * (radius + glm::length(position - centre));
    return lod::Camera(position, look_at, kFovYDegrees, viewport, 1.0, std::max(far_m, 2.0));
}

} // namespace ridge::stream
