#pragma once
// Every sample of a patch as a mesh (internal to ridge_render): one index buffer shared by all
// patches of an archive, drawn instanced over shaders/chunk.vert — two triangles per cell,
// then the skirt, a quad under each border cell. The chunked-LOD grid and the brute-force
// baseline draw with it.
#include "ridge/gpu/gl_objects.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace ridge::render {

// The index list: cells a=(i,j), b=(i+1,j), c=(i,j+1), d=(i+1,j+1) as (a,b,c), (b,d,c), one
// diagonal (Err(P) holds for either); then for each border cell in ring order (north row west
// to east, east column, south row east to west, west column) a skirt quad whose first and
// last vertices are feet n² + k (capture tests tell skirt triangles by their first vertex,
// shading reads the last). Plain C++, tested without GL.
std::vector<uint32_t> patchGridIndices(int patch_size, size_t* surface_indices);

class PatchGridMesh {
  public:
    // Needs a current GL context.
    explicit PatchGridMesh(int patch_size);
    // Draws `count` instances from the bound program (chunk.vert reads the instance records).
    void draw(size_t count, bool skirts) const;
    size_t trianglesPerInstance(bool skirts) const { return size_t(skirts ? all_ : surface_) / 3; }

  private:
    gpu::GlVertexArray vao_;
    gpu::GlBuffer indices_;
    GLsizei surface_ = 0, all_ = 0;
};

} // namespace ridge::render
