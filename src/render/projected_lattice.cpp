#include "projected_lattice.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace ridge::render {

namespace {

void setVec3(GLuint program, GLint location, glm::dvec3 v)
{
    glProgramUniform3f(program, location, float(v.x), float(v.y), float(v.z));
}

// The four layers of every node of `grid`, as `value(node, layer)` gives them, into `texture`.
template <typename Value>
void fillLattice(GLuint texture, const lod::ProjectedGrid& grid, std::vector<float>& staging,
                 Value value)
{
    const int nx = grid.nodesX(), ny = grid.nodesY();
    staging.resize(size_t(nx) * size_t(ny) * 4);
    for (int layer = 0; layer < 4; ++layer) {
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i) {
                const glm::dvec3 v = value(i, j, layer);
                float* out = &staging[(size_t(j) * nx + i) * 4];
                out[0] = float(v.x);
                out[1] = float(v.y);
                out[2] = float(v.z);
                out[3] = 0.f;
            }
        glTextureSubImage3D(texture, 0, 0, 0, layer, nx, ny, 1, GL_RGBA, GL_FLOAT, staging.data());
    }
}

void allocateLattice(GLuint texture, const lod::ProjectedGrid& grid)
{
    glTextureStorage3D(texture, 1, GL_RGBA32F, grid.nodesX(), grid.nodesY(), 4);
    glTextureParameteri(texture, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(texture, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
}

} // namespace

ProjectedLattice::ProjectedLattice(const lod::ProjectedGrid& grid) : grid_(grid)
{
    allocateLattice(texture_.id(), grid);
}

void ProjectedLattice::update(int li, int lj)
{
    const lod::LatticeNode& l = grid_.node(li, lj);
    const double h = grid_.step();
    fillLattice(texture_.id(), grid_, staging_, [&](int i, int j, int layer) {
        const lod::LatticeNode& n = grid_.node(i, j);
        switch (layer) {
        case 0:
            return n.s - l.s - l.s_c * ((i - li) * h) - l.s_r * ((j - lj) * h);
        case 1:
            return h * (n.s_c - l.s_c);
        case 2:
            return h * (n.s_r - l.s_r);
        default:
            return h * h * n.s_cr;
        }
    });
    li_ = li;
    lj_ = lj;
}

void ProjectedLattice::set(const gpu::ShaderProgram& program, const CameraAnchor& anchor)
{
    const int64_t h = grid_.step();
    auto nearest = [&](int64_t sample, int first, int nodes) {
        const double k = std::round(double(sample - first) / double(h));
        return int(std::clamp(k, 0.0, double(nodes - 1)));
    };
    const int li = nearest(anchor.column, grid_.firstColumn(), grid_.nodesX());
    const int lj = nearest(anchor.row, grid_.firstRow(), grid_.nodesY());
    if (li != li_ || lj != lj_)
        update(li, lj);
    const lod::LatticeNode& l = grid_.node(li, lj);
    const glm::dvec3 normal = grid_.normalThrough(l.s);
    const glm::dvec3 m(l.s.x, l.s.y, l.s.z / (1.0 - grid_.ellipsoid().e2()));

    const GLuint id = program.id();
    glProgramUniform1i(id, program.uniform("u_lattice_step"), int(h));
    glProgramUniform2i(id, program.uniform("u_lattice_nodes"), grid_.nodesX(), grid_.nodesY());
    glProgramUniform2i(id, program.uniform("u_lattice_node"), li, lj);
    glProgramUniform2i(id, program.uniform("u_lattice_delta"),
                       int(anchor.column - (grid_.firstColumn() + li * h)),
                       int(anchor.row - (grid_.firstRow() + lj * h)));
    setVec3(id, program.uniform("u_lattice_s_c"), l.s_c);
    setVec3(id, program.uniform("u_lattice_s_r"), l.s_r);
    setVec3(id, program.uniform("u_lattice_base"), l.s + anchor.height * normal - anchor.camera);
    setVec3(id, program.uniform("u_lattice_normal"), normal);
    glProgramUniform1f(id, program.uniform("u_lattice_m_norm"), float(glm::length(m)));
    glProgramUniform1f(id, program.uniform("u_reference_height"), float(anchor.height));
    glBindTextureUnit(kLatticeTextureUnit, texture_.id());
}

gpu::GlTexture absoluteLatticeTexture(const lod::ProjectedGrid& grid)
{
    gpu::GlTexture texture(GL_TEXTURE_2D_ARRAY);
    allocateLattice(texture.id(), grid);
    const double h = grid.step();
    std::vector<float> staging;
    fillLattice(texture.id(), grid, staging, [&](int i, int j, int layer) {
        const lod::LatticeNode& n = grid.node(i, j);
        return layer == 0 ? n.s : layer == 1 ? h * n.s_c : layer == 2 ? h * n.s_r : h * h * n.s_cr;
    });
    return texture;
}

} // namespace ridge::render
