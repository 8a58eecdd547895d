// Scheme "tess": the hardware-tessellation paper (Yusov & Shevtsov 2011, §5). Coarse LOD is
// the patch quadtree at ε; fine LOD is the tessellation control shader's per-edge factors from
// the blocks' Λ^(d) = λ^(d) + Err(P) (shaders/terrain.tesc, edge_tessellation.glsl); every
// selected patch is one instance of one draw, B² tessellation blocks plus 4B skirt segments.
#include "../frame_uniforms.h"
#include "../scheme_programs.h"
#include "../terrain_scheme.h"

#include "ridge/lod/frustum.h"

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>

namespace ridge::render {
namespace {

class TessellationScheme final : public TerrainScheme {
  public:
    explicit TessellationScheme(const SchemeResources& r)
        : textures_(r.textures), blocks_per_side_(r.reader.blockLayout().blocksPerSide()),
          block_cells_(r.reader.blockLayout().block_cells),
          block_levels_(std::min(r.reader.blockLayout().levels(), lod::kMaxBlockLevels)),
          // One variant per lod::TessellationRule, in its order: conservative (ridge's
          // default, ε on every sample), the paper's edge rule.
          programs_(r,
                    {{GL_VERTEX_SHADER, "terrain.vert"},
                     {GL_TESS_CONTROL_SHADER, "terrain.tesc"},
                     {GL_TESS_EVALUATION_SHADER, "terrain.tese"}},
                    {{"RIDGE_TESSELLATION_RULE 0"}, {"RIDGE_TESSELLATION_RULE 1"}})
    {
    }

    // The skirts hang by the tessellator's λ: what a simplified block may drop beyond Err(P).
    double meshDeviation(int slot) const override { return double(textures_.lambdaMax(slot)); }

    std::array<const gpu::ShaderProgram*, 2> programs(bool capture, bool fading,
                                                      const RenderSettings& settings) override
    {
        return programs_.get(capture, fading, size_t(settings.tessellation_rule));
    }

    // What only the tessellation shaders read: the LOD camera, ε and the rule for the edge
    // factors (edge_tessellation.glsl), and the blocks and frustum for block culling
    // (terrain.tesc).
    void setUniforms(const gpu::ShaderProgram& program, const SchemeFrame& frame) const override
    {
        const GLuint id = program.id();
        const lod::Camera& camera = frame.camera;
        const RenderSettings& settings = frame.settings;
        // LOD is decided for frame.lod_camera: positions relative to the drawn camera, moved to
        // the LOD camera and projected by it (the same matrix when both are one camera).
        const glm::dmat4 to_lod_camera =
            glm::translate(glm::dmat4(1.0), camera.position() - frame.lod_camera.position());
        setMatrix(program, "u_lod_view_projection",
                  reverseZProjection(frame.lod_camera) * frame.lod_camera.view() * to_lod_camera);
        const glm::dvec3 lod_offset = frame.lod_camera.position() - camera.position();
        glProgramUniform3f(id, program.uniform("u_lod_camera"), float(lod_offset.x),
                           float(lod_offset.y), float(lod_offset.z));
        glProgramUniform2f(id, program.uniform("u_viewport"), float(camera.viewport().width),
                           float(camera.viewport().height));
        glProgramUniform1f(id, program.uniform("u_epsilon"), float(settings.epsilon_px));
        glProgramUniform1i(id, program.uniform("u_blocks_per_side"), blocks_per_side_);
        glProgramUniform1i(id, program.uniform("u_block_levels"), block_levels_);
        // Block culling uses the camera-relative frustum: the terrain-frame planes moved by −c.
        glProgramUniform1i(id, program.uniform("u_cull_blocks"),
                           settings.cull && settings.cull_blocks ? 1 : 0);
        const lod::Frustum frustum(camera);
        float planes[6][4];
        for (int i = 0; i < 6; ++i) {
            const glm::dvec4 pl = frustum.plane(i);
            const double d = pl.w + glm::dot(glm::dvec3(pl), camera.position());
            planes[i][0] = float(pl.x);
            planes[i][1] = float(pl.y);
            planes[i][2] = float(pl.z);
            // Widened beyond float rounding of camera-relative positions (~1e-7 of the
            // distance): a visible block must never be culled.
            planes[i][3] = float(d + 0.01 + 1e-6 * camera.farPlane());
        }
        glProgramUniform4fv(id, program.uniform("u_frustum"), 6, &planes[0][0]);
    }

    void draw(const gpu::ShaderProgram& program, const SchemeFrame& frame, size_t first,
              size_t count) const override
    {
        glUniform1i(program.uniform("u_instance_offset"), GLint(first));
        glBindVertexArray(empty_vao_.id());
        glPatchParameteri(GL_PATCH_VERTICES, 1);
        const int skirt_segments = frame.settings.skirts ? 4 * blocks_per_side_ : 0;
        glDrawArraysInstanced(GL_PATCHES, 0, blocks_per_side_ * blocks_per_side_ + skirt_segments,
                              GLsizei(count));
    }

    // A block yields at most 2·b² triangles plus its transition ring, a skirt segment 4·b.
    size_t maxTrianglesPerInstance(bool skirts) const override
    {
        const size_t b = size_t(block_cells_), B = size_t(blocks_per_side_);
        return B * B * (2 * b * b + 8 * b) + (skirts ? 4 * B * (4 * b + 4) : 0);
    }

  private:
    const PatchTextures& textures_;
    int blocks_per_side_, block_cells_;
    int block_levels_;             // D as the shaders use it (<= lod::kMaxBlockLevels)
    gpu::GlVertexArray empty_vao_; // the tessellator's one vertex per patch primitive is implicit
    SchemePrograms programs_;
};

} // namespace

SchemeInfo tessellationScheme()
{
    return {
        .name = "tess",
        .description = "the paper's hardware tessellation: per-edge factors inside each patch",
        .options = {},
        .needs = [](const archive::ArchiveReader&, const lod::TerrainFrame&, const RendererOptions&,
                    const SchemeOptions&) { return SchemeNeeds{}; },
        .make = [](const SchemeResources& r) -> std::unique_ptr<TerrainScheme> {
            return std::make_unique<TessellationScheme>(r);
        },
        // An arrival fades from its ancestors' grids (linear on their cells split along the
        // anti-diagonal), but the tessellator split the stand-in's cells its own way (the
        // quad domain's diagonals are the implementation's): the arrival frame jumps by that
        // difference, large over a coarse ancestor's cells (11.7 of 14.2 px on the Everest
        // fixture; conformance suite). Drawing stand-ins at their full factors did not help.
        .promises = {.arrivals = SchemePromises::Arrivals::FadeFromGrid},
    };
}

} // namespace ridge::render
