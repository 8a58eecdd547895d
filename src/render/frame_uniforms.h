#pragma once
// The frame uniforms every scheme's terrain programs share (internal to ridge_render): the
// geometry of shaders/terrain_common.glsl — view-projection, camera anchor, height decoding,
// patch and block cells — for every program a scheme draws or captures with, and the shading
// of terrain.frag for the drawing ones. Uniforms that only one scheme's shaders read are that
// scheme's (TerrainScheme::setUniforms: the tessellation scheme's LOD camera, ε, block
// culling).
#include "patch_instances.h"
#include "projected_lattice.h"

#include "ridge/archive/archive_reader.h"
#include "ridge/gpu/shader_program.h"
#include "ridge/lod/camera.h"
#include "ridge/lod/patch_quadtree.h"
#include "ridge/render/terrain_renderer.h"

#include <glm/mat4x4.hpp>

#include <memory>

namespace ridge::render {

// Sets the mat4 uniform `name` of `program` to `m`, in floats.
void setMatrix(const gpu::ShaderProgram& program, const char* name, const glm::dmat4& m);

class FrameUniforms {
  public:
    // `reader` and `quadtree` must outlive this. Needs a current GL context when the quadtree's
    // frame is a projected grid (its lattice texture).
    FrameUniforms(const archive::ArchiveReader& reader, const lod::PatchQuadtree& quadtree);

    // terrain_common.glsl's uniforms of `program` for a frame drawn from `camera` with
    // `settings`.
    void setGeometry(const gpu::ShaderProgram& program, const lod::Camera& camera,
                     const RenderSettings& settings) const;
    // terrain.frag's: sun, height range, sea level, the water rule, fog, the wireframe's
    // colour and the palette.
    void setShading(const gpu::ShaderProgram& program, const lod::Camera& camera,
                    const RenderSettings& settings) const;

  private:
    // The frame's surface and, on a globe, the anchor's geodetic terms (framePoint).
    void setSurface(const gpu::ShaderProgram& program, const CameraAnchor& anchor) const;

    const archive::ArchiveReader& reader_;
    const lod::PatchQuadtree& quadtree_;
    float min_height_ = 0.f, max_height_ = 0.f; // terrain frame, metres
    // A projected grid's lattice relative to the node nearest the camera: a cache the frame's
    // anchor refreshes (its texture changes only when the camera reaches another node).
    std::unique_ptr<ProjectedLattice> lattice_;
};

} // namespace ridge::render
