#pragma once
// The instance buffer of the terrain draw (internal to ridge_render): one frame's instance
// records (patch_instances.h) for a scheme — skirts hung by what its mesh drops beyond Err(P),
// what it keeps in the records filled in — in the shader storage buffer every terrain program
// reads (shaders/terrain_common.glsl's PatchInstances).
#include "patch_instances.h"
#include "record_buffer.h"

#include "ridge/gpu/gl_objects.h"
#include "ridge/gpu/shader_program.h"
#include "ridge/lod/arrival_blend.h"
#include "ridge/lod/patch_quadtree.h"
#include "ridge/lod/patch_residency.h"
#include "ridge/render/terrain_renderer.h"

#include <array>
#include <cstddef>

namespace ridge::render {

class TerrainScheme;

class InstanceBuffer {
  public:
    // `quadtree` and `residency` must outlive this.
    InstanceBuffer(const lod::PatchQuadtree& quadtree, const lod::PatchResidency& residency);

    // The records of `selection` (resident) seen from `camera` as `scheme` draws it with
    // `settings` (the ε met), LOD decided for `lod_camera`, uploaded; returns them.
    // A scheme that builds its own records (TerrainScheme::buildInstances) gives them instead.
    // `arrivals`: the fades of arriving patches (streaming), put in the records while the
    // ancestor they fade from is resident.
    PatchInstances write(TerrainScheme& scheme, const lod::Camera& camera,
                         const lod::Camera& lod_camera, const lod::Selection& selection,
                         const RenderSettings& settings,
                         const lod::ArrivalBlends* arrivals = nullptr);
    // Binds the buffer to shader storage binding 0.
    void bind() const;

  private:
    const lod::PatchQuadtree& quadtree_;
    const lod::PatchResidency& residency_;
    float min_height_ = 0.f, max_height_ = 0.f; // terrain frame, metres
    double skirt_margin_ = 0.0;                 // float rounding of camera-relative heights
    RecordBuffer<GpuPatchInstance> records_;
};

// Calls draw(program, first, count) for each non-empty group of `instances`
// (instanceGroups) with the program `scheme` draws it with (TerrainScheme::programs): its
// plain (or capture) program or its clipping one, each in its fading variant for the
// patches that fade in.
template <class Scheme, class Draw>
void forEachGroup(Scheme& scheme, bool capture, const RenderSettings& settings,
                  const PatchInstances& instances, Draw&& draw)
{
    for (const InstanceGroup& g : instanceGroups(instances))
        if (g.count)
            draw(*scheme.programs(capture, g.fading, settings)[g.clipped ? 1 : 0], g.first,
                 g.count);
}

} // namespace ridge::render
