#include "patch_grid_mesh.h"

namespace ridge::render {

std::vector<uint32_t> patchGridIndices(int patch_size, size_t* surface_indices)
{
    const uint32_t C = uint32_t(patch_size - 1), N = uint32_t(patch_size);
    std::vector<uint32_t> indices;
    indices.reserve(size_t(C) * C * 6 + size_t(4) * C * 6);
    for (uint32_t j = 0; j < C; ++j)
        for (uint32_t i = 0; i < C; ++i) {
            const uint32_t a = j * N + i, b = a + 1, c = a + N, d = c + 1;
            indices.insert(indices.end(), {a, b, c, b, d, c});
        }
    if (surface_indices)
        *surface_indices = indices.size();
    auto ring = [&](uint32_t k) -> uint32_t {
        if (k < C)
            return k; // north row
        if (k < 2 * C)
            return (k - C) * N + C; // east column
        if (k < 3 * C)
            return C * N + (C - (k - 2 * C)); // south row, east to west
        return (C - (k - 3 * C)) * N;         // west column, south to north
    };
    const uint32_t R = 4 * C;
    for (uint32_t k = 0; k < R; ++k) {
        const uint32_t t0 = ring(k), t1 = ring((k + 1) % R);
        const uint32_t f0 = N * N + k, f1 = N * N + (k + 1) % R;
        indices.insert(indices.end(), {f0, t0, t1, f0, t1, f1});
    }
    return indices;
}

PatchGridMesh::PatchGridMesh(int patch_size)
{
    size_t surface = 0;
    const std::vector<uint32_t> indices = patchGridIndices(patch_size, &surface);
    surface_ = GLsizei(surface);
    all_ = GLsizei(indices.size());
    glNamedBufferStorage(indices_.id(), GLsizeiptr(indices.size() * sizeof(uint32_t)),
                         indices.data(), 0);
    glVertexArrayElementBuffer(vao_.id(), indices_.id());
    gpu::checkGlError("terrain renderer: patch grid mesh");
}

void PatchGridMesh::draw(size_t count, bool skirts) const
{
    glBindVertexArray(vao_.id());
    glDrawElementsInstanced(GL_TRIANGLES, skirts ? all_ : surface_, GL_UNSIGNED_INT, nullptr,
                            GLsizei(count));
}

} // namespace ridge::render
