#pragma once
// A projected grid's lattice on the GPU (internal to ridge_render): what framePoint's projected
// branch (shaders/terrain_common.glsl) reads to place a sample, and the grid's axes on the
// ground that the normal maps are turned by (patch_normals.comp).
//
// The lattice (lod/projected_grid.h) is sent relative to the node L nearest the camera, in
// double on the CPU: per node the residual R = S − S_L − J·(node − L) and its Hermite
// derivatives, J = ∂S/∂(c, r) at L. Both J·d and R are small near the camera, so floats keep
// their relative precision where it matters. The texture changes only when the camera moves
// to another node (every `step` samples), never within one: no jitter.
#include "patch_instances.h"

#include "ridge/gpu/gl_objects.h"
#include "ridge/gpu/shader_program.h"
#include "ridge/lod/projected_grid.h"

#include <vector>

namespace ridge::render {

// The texture unit framePoint's lattice is bound to (terrain_common.glsl's u_lattice).
inline constexpr int kLatticeTextureUnit = 9;
// The unit patch_normals.comp reads the absolute lattice from (its u_lattice).
inline constexpr int kLatticeNormalsTextureUnit = 10;

class ProjectedLattice {
  public:
    // `grid` must outlive this. Needs a current GL context.
    explicit ProjectedLattice(const lod::ProjectedGrid& grid);

    // framePoint's lattice uniforms of `program` for `anchor`, the texture made relative to
    // the node nearest it and bound.
    void set(const gpu::ShaderProgram& program, const CameraAnchor& anchor);

  private:
    void update(int li, int lj);

    const lod::ProjectedGrid& grid_;
    gpu::GlTexture texture_{GL_TEXTURE_2D_ARRAY};
    int li_ = -1, lj_ = -1; // node L the texture is relative to
    std::vector<float> staging_;
};

// The lattice as it is, RGBA32F, four layers per node: S, h·∂S/∂c, h·∂S/∂r, h²·∂²S/∂c∂r
// (metres, ECEF). Float S is good to ~0.5 m: enough for directions (patch_normals.comp turns
// normals by the grid's tangents through it), never for positions.
gpu::GlTexture absoluteLatticeTexture(const lod::ProjectedGrid& grid);

} // namespace ridge::render
