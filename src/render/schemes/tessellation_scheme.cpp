// Scheme "tess": the hardware-tessellation paper (Yusov & Shevtsov 2011, §5). Coarse LOD is
// the patch quadtree at ε; fine LOD is the tessellation control shader's per-edge factors from
// the blocks' Λ^(d) = λ^(d) + Err(P) (shaders/terrain.tesc, edge_tessellation.glsl); every
// selected patch is one instance of one draw, B² tessellation blocks plus 4B skirt segments.
#include "../scheme_programs.h"
#include "../terrain_scheme.h"

namespace ridge::render {
namespace {

class TessellationScheme final : public TerrainScheme {
  public:
    explicit TessellationScheme(const SchemeResources& r)
        : textures_(r.textures), blocks_per_side_(r.reader.blockLayout().blocksPerSide()),
          block_cells_(r.reader.blockLayout().block_cells)
    {
    }

    // The skirts hang by the tessellator's λ: what a simplified block may drop beyond Err(P).
    double meshDeviation(int slot) const override { return double(textures_.lambdaMax(slot)); }

    std::array<const gpu::ShaderProgram*, 2> programs(bool capture) override
    {
        return programs_.get(capture);
    }

    // Conservative (ridge's default: ε on every sample) or the paper's edge rule.
    void setUniforms(const gpu::ShaderProgram& program, const SchemeFrame& frame) const override
    {
        glProgramUniform1i(program.id(), program.uniform("u_tessellation_rule"),
                           int(frame.settings.tessellation_rule));
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
    gpu::GlVertexArray empty_vao_; // the tessellator's one vertex per patch primitive is implicit
    SchemePrograms programs_{{{GL_VERTEX_SHADER, "terrain.vert"},
                              {GL_TESS_CONTROL_SHADER, "terrain.tesc"},
                              {GL_TESS_EVALUATION_SHADER, "terrain.tese"}}};
};

} // namespace

SchemeInfo tessellationScheme()
{
    return {
        .name = "tess",
        .description = "the paper's hardware tessellation: per-edge factors inside each patch",
        .options = {},
        .needs = [](const archive::ArchiveReader&, const RendererOptions&,
                    const SchemeOptions&) { return SchemeNeeds{}; },
        .make = [](const SchemeResources& r) -> std::unique_ptr<TerrainScheme> {
            return std::make_unique<TessellationScheme>(r);
        },
    };
}

} // namespace ridge::render
