#include "instance_buffer.h"

#include "terrain_scheme.h"

#include <algorithm>
#include <cmath>

namespace ridge::render {

InstanceBuffer::InstanceBuffer(const lod::PatchQuadtree& quadtree,
                               const lod::PatchResidency& residency)
    : quadtree_(quadtree), residency_(residency)
{
    const lod::PatchBounds& root = quadtree.bounds(PatchId{0, 0, 0});
    min_height_ = root.min_height;
    max_height_ = root.max_height;
    // Float rounding of camera-relative heights: a centimetre plus a few ulps of the highest.
    skirt_margin_ = 0.01 + 1e-6 * std::max(std::abs(root.min_height), std::abs(root.max_height));
}

PatchInstances InstanceBuffer::write(TerrainScheme& scheme, const lod::Camera& camera,
                                     const lod::Camera& lod_camera, const lod::Selection& selection,
                                     const RenderSettings& settings,
                                     const lod::ArrivalBlends* arrivals)
{
    // Skirts hang by what the scheme's mesh drops beyond Err(P) (the tessellator's λ, a
    // chunk's simplification error, ...).
    // Camera-relative heights are floats: a skirt must also hang a few ulps of the largest
    // |z − camera z| (2^−22 ≈ 2.4e−7 of it, times 4), or over flat ground (Err and λ 0), seen
    // from far above, its foot rounds onto its top and the seam it closes opens (found when
    // the texture-detail criterion split flat sea into levels seen from 760 km).
    const double k = settings.exaggeration;
    const double reference = quadtree_.frame().referenceHeight(camera.position());
    const double z_rel = std::max(std::abs(reference - k * double(min_height_)),
                                  std::abs(reference - k * double(max_height_)));
    PatchInstances built;
    if (!scheme.buildInstances(camera, settings, built))
        built = buildPatchInstances(
            quadtree_, selection, camera.position(),
            [&](PatchId p) { return residency_.slotOf(p); },
            [&](PatchId p) { return scheme.meshDeviation(residency_.slotOf(p)); },
            skirt_margin_ * std::max(k, 1.0) + 1e-6 * z_rel, k,
            [&](PatchId p) -> std::optional<InstanceBlend> {
                std::optional<InstanceBlend> b;
                if (const std::optional<lod::ArrivalBlend> chain =
                        arrivals ? arrivals->of(p) : std::nullopt) {
                    InstanceBlend ib{*chain, {}};
                    ib.chain.depth = 0; // up to the first ancestor that is not resident
                    for (int l = 0; l < chain->depth; ++l) {
                        const int slot = residency_.slotOf(chain->links[size_t(l)].from);
                        if (slot < 0)
                            break;
                        ib.slots[size_t(l)] = slot;
                        ib.chain.depth = l + 1;
                    }
                    if (ib.chain.depth > 0)
                        b = ib;
                }
                return b;
            });
    if (arrivals)
        for (size_t i = 0; i < built.records.size(); ++i)
            built.records[i].stand_in = arrivals->standsIn(built.patches[i]);
    groupFadingLast(built);
    scheme.completeInstances(lod_camera, settings, built);
    records_.upload(built.records);
    return built;
}

void InstanceBuffer::bind() const
{
    records_.bind(0);
}

} // namespace ridge::render
