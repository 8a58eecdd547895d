// Scheme "brute": the finest level wherever the view frustum lets it (ε = 0), every sample a
// vertex — the yardstick every LOD scheme is measured against (frustum culling only).
#include "../patch_grid_mesh.h"
#include "../scheme_programs.h"
#include "../terrain_scheme.h"

namespace ridge::render {
namespace {

class BruteForceScheme final : public TerrainScheme {
  public:
    explicit BruteForceScheme(const SchemeResources& r)
        : grid_(r.reader.geometry().patchSize()), programs_(r, {{GL_VERTEX_SHADER, "chunk.vert"}})
    {
    }

    // ε = 0 refines to the finest level wherever the frustum lets it (a view that needs more
    // patches than slots still raises it: Selection::epsilon_px says so).
    void adjustSelection(const RenderSettings&, lod::SelectionSettings& s) const override
    {
        s.epsilon_px = 0.0;
    }
    // Every sample is drawn: the mesh is the patch's own samples.
    double meshDeviation(int) const override { return 0.0; }

    std::array<const gpu::ShaderProgram*, 2> programs(bool capture, bool fading,
                                                      const RenderSettings&) override
    {
        return programs_.get(capture, fading);
    }
    void draw(const gpu::ShaderProgram& program, const SchemeFrame& frame, size_t first,
              size_t count) const override
    {
        glUniform1i(program.uniform("u_instance_offset"), GLint(first));
        grid_.draw(count, frame.settings.skirts);
    }
    size_t maxTrianglesPerInstance(bool skirts) const override
    {
        return grid_.trianglesPerInstance(skirts);
    }

  private:
    PatchGridMesh grid_;
    SchemePrograms programs_;
};

} // namespace

SchemeInfo bruteForceScheme()
{
    return {
        .name = "brute",
        .description = "brute force: the finest level everywhere in view, every sample a vertex",
        .options = {},
        .needs = [](const archive::ArchiveReader&, const lod::TerrainFrame&, const RendererOptions&,
                    const SchemeOptions&) { return SchemeNeeds{}; },
        .make = [](const SchemeResources& r) -> std::unique_ptr<TerrainScheme> {
            return std::make_unique<BruteForceScheme>(r);
        },
    };
}

} // namespace ridge::render
