#include "patch_instances.h"

#include "ridge/core/error.h"
#include "ridge/lod/screen_space_error.h"
#include "ridge/lod/skirt_depth.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace ridge::render {

CameraAnchor cameraAnchor(const lod::TerrainFrame& frame, glm::dvec3 camera_position)
{
    // Clamped to 2^40 samples beyond the grid, whatever the camera and spacing: the origins
    // below are differences of int64 columns and must not overflow (a camera 1e15 m away
    // over a millimetre grid is 1e18 samples out). Such an anchor is still a sample, so seams
    // stay bit-identical; only the precision near a camera that far out is lost.
    constexpr double kReach = 0x1p40;
    CameraAnchor a;
    a.camera = camera_position;
    if (frame.onEllipsoid()) {
        // The sample nearest the camera (its column in the first period of a wrapping grid,
        // or the period nearest the grid): offsets from it stay within 2^24, which floats
        // hold exactly, for any grid of fewer than 2^22 samples a side.
        const glm::dvec3 g = frame.gridOf(camera_position);
        a.column = int64_t(std::llround(g.x));
        a.row = int64_t(std::llround(g.y));
        a.column_fraction = g.x - double(a.column);
        a.row_fraction = g.y - double(a.row);
        if (!frame.projectedGrid()) {
            a.longitude = frame.longitudeOf(g.x);
            a.latitude = frame.geodetic().lat0 + g.y * frame.geodetic().dlat;
        }
        a.height = g.z;
        return a;
    }
    const double column = std::clamp(frame.columnOf(camera_position.x), -kReach, kReach);
    const double row = std::clamp(frame.rowOf(camera_position.y), -kReach, kReach);
    a.column = int64_t(std::llround(column));
    a.row = int64_t(std::llround(row));
    a.x_rel = frame.xOf(double(a.column)) - camera_position.x;
    a.y_rel = frame.yOf(double(a.row)) - camera_position.y;
    a.height = camera_position.z;
    return a;
}

PatchInstances
buildPatchInstances(const lod::PatchQuadtree& tree, const lod::Selection& selection,
                    glm::dvec3 camera_position, const std::function<int(PatchId)>& slot_of,
                    const std::function<double(PatchId)>& lambda_max, double skirt_margin,
                    double exaggeration,
                    const std::function<std::optional<InstanceBlend>(PatchId)>& blend_of)
{
    const double k = exaggeration;
    const PyramidGeometry& g = tree.geometry();

    // Front to back by box distance (early depth rejection does the rest), whole patches
    // first.
    std::vector<std::pair<double, PatchId>> order;
    order.reserve(selection.patches.size());
    for (const lod::SelectedPatch& s : selection.patches)
        order.push_back({lod::distanceToBox(camera_position, tree.box(s.id, k)), s.id});
    std::sort(order.begin(), order.end(),
              [](const auto& a, const auto& b) { return a.first < b.first; });
    const auto split = std::stable_partition(order.begin(), order.end(),
                                             [&](const auto& e) { return g.whole(e.second); });

    PatchInstances out;
    out.whole = size_t(split - order.begin());
    out.partial = order.size() - out.whole;
    for (const auto& entry : order)
        out.patches.push_back(entry.second);
    std::vector<std::optional<InstanceBlend>> blends(out.patches.size());
    if (blend_of)
        for (size_t i = 0; i < out.patches.size(); ++i)
            blends[i] = blend_of(out.patches[i]);
    const std::vector<double> depths = lod::skirtDepths(
        tree, out.patches,
        [&](PatchId p) {
            // On a globe two neighbours' borders drawn at different spacings part by up to
            // the sag of the longer straight edge (at most the patch's side); 0 on a plane.
            // (The depth this sums to is capped below.)
            const lod::TerrainFrame& f = tree.frame();
            const double sag =
                f.onEllipsoid() ? f.edgeSag(double(g.step(p.level)) * g.cells()) : 0.0;
            double deviation = double(tree.bounds(p).err) + lambda_max(p);
            // A fading surface lies between its own and its ancestors', each within its Err of
            // the finest samples.
            if (blend_of)
                if (const std::optional<InstanceBlend> b = blend_of(p))
                    for (int l = 0; l < b->chain.depth; ++l)
                        deviation = std::max(
                            deviation, double(tree.bounds(b->chain.links[size_t(l)].from).err));
            return k * deviation + sag;
        },
        skirt_margin);

    const CameraAnchor anchor = cameraAnchor(tree.frame(), camera_position);
    out.records.reserve(order.size());
    for (size_t i = 0; i < out.patches.size(); ++i) {
        const PatchId p = out.patches[i];
        const lod::PatchBounds& b = tree.bounds(p);
        const int64_t step = g.step(p.level);
        GpuPatchInstance r{};
        r.origin[0] = int32_t(int64_t(p.x) * g.cells() * step - anchor.column);
        r.origin[1] = int32_t(int64_t(p.y) * g.cells() * step - anchor.row);
        r.step = int32_t(step);
        r.layer = slot_of(p);
        r.level = p.level;
        // Rounded up: the shaders' Λ must not understate the exaggerated Err(P).
        r.err = k == 1.0 ? b.err : std::nextafter(float(k * double(b.err)), INFINITY);
        // On a globe the depth is capped at half the polar radius: a foot deeper would reach
        // the polar axis, where the normal's foot crosses to the far meridian and
        // the clip shader's meridian cuts lose their meaning. A gap between neighbours is
        // never that large (the sag of a 90° chord is 1,870 km).
        r.skirt_depth = float(tree.frame().onEllipsoid()
                                  ? std::min(depths[i], 0.5 * tree.frame().geodetic().ellipsoid.b())
                                  : depths[i]);
        r.min_z = float(k * double(b.min_height) - anchor.height);
        r.max_z = float(k * double(b.max_height) - anchor.height);
        // Exact while a patch spans < 2^24 finest samples (the fraction is a multiple of 1/step);
        // beyond, rounded to float like the shader's cell coordinates it is compared with.
        r.valid_extent[0] = float(g.validExtentX(p));
        r.valid_extent[1] = float(g.validExtentY(p));
        if (const std::optional<InstanceBlend>& b = blends[i])
            for (int l = 0; l < b->chain.depth; ++l) {
                // The ancestor's sample (0, 0), spacing and slot, its heights within the bounds.
                const PatchId a = b->chain.links[size_t(l)].from;
                const int64_t s = g.step(a.level);
                r.fade_origin[l][0] = int32_t(int64_t(a.x) * g.cells() * s - anchor.column);
                r.fade_origin[l][1] = int32_t(int64_t(a.y) * g.cells() * s - anchor.row);
                r.fade_step[l] = int32_t(s);
                r.fade_layer[l] = b->slots[size_t(l)];
                r.fade_weight[l] = b->chain.links[size_t(l)].weight;
                const lod::PatchBounds& ab = tree.bounds(a);
                r.min_z = std::min(r.min_z, float(k * double(ab.min_height) - anchor.height));
                r.max_z = std::max(r.max_z, float(k * double(ab.max_height) - anchor.height));
            }
        out.records.push_back(r);
    }
    return out;
}

std::array<InstanceGroup, 4> instanceGroups(const PatchInstances& in)
{
    const size_t whole_plain = in.whole - in.whole_fading;
    const size_t partial_plain = in.partial - in.partial_fading;
    return {{{0, whole_plain, false, false},
             {whole_plain, in.whole_fading, false, true},
             {in.whole, partial_plain, true, false},
             {in.whole + partial_plain, in.partial_fading, true, true}}};
}

void groupFadingLast(PatchInstances& in)
{
    if (in.records.size() != in.total() || in.patches.size() != in.total())
        throw Error("patch instances: " + std::to_string(in.records.size()) + " records and " +
                    std::to_string(in.patches.size()) + " patches for " +
                    std::to_string(in.total()) + " instances");
    std::vector<size_t> order(in.total());
    for (size_t i = 0; i < order.size(); ++i)
        order[i] = i;
    const auto plain = [&](size_t i) { return !(in.records[i].fade_weight[0] > 0.f); };
    const auto whole_end = order.begin() + std::ptrdiff_t(in.whole);
    in.whole_fading = size_t(whole_end - std::stable_partition(order.begin(), whole_end, plain));
    in.partial_fading = size_t(order.end() - std::stable_partition(whole_end, order.end(), plain));
    if (in.whole_fading == 0 && in.partial_fading == 0)
        return;
    std::vector<GpuPatchInstance> records(order.size());
    std::vector<PatchId> patches(order.size());
    for (size_t i = 0; i < order.size(); ++i) {
        records[i] = in.records[order[i]];
        patches[i] = in.patches[order[i]];
    }
    in.records = std::move(records);
    in.patches = std::move(patches);
}

} // namespace ridge::render
