#include "frame_uniforms.h"

#include "palette_uniforms.h"
#include "patch_instances.h"
#include "sky.h"

#include <glm/geometric.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>

namespace ridge::render {

void setMatrix(const gpu::ShaderProgram& program, const char* name, const glm::dmat4& m)
{
    const glm::mat4 f(m);
    glProgramUniformMatrix4fv(program.id(), program.uniform(name), 1, GL_FALSE, glm::value_ptr(f));
}

FrameUniforms::FrameUniforms(const archive::ArchiveReader& reader,
                             const lod::PatchQuadtree& quadtree)
    : reader_(reader), quadtree_(quadtree)
{
    const lod::PatchBounds& root = quadtree.bounds(PatchId{0, 0, 0});
    min_height_ = root.min_height;
    max_height_ = root.max_height;
}

void FrameUniforms::setGeometry(const gpu::ShaderProgram& program, const lod::Camera& camera,
                                const RenderSettings& settings) const
{
    const GLuint id = program.id();
    setMatrix(program, "u_view_projection", reverseZProjection(camera) * camera.view());
    const lod::TerrainFrame& frame = quadtree_.frame();
    const CameraAnchor anchor = cameraAnchor(frame, camera.position());
    glProgramUniform2f(id, program.uniform("u_spacing"), float(frame.spacingX()),
                       float(-frame.spacingY()));
    glProgramUniform2f(id, program.uniform("u_anchor_offset"), float(anchor.x_rel),
                       float(anchor.y_rel));
    // Exaggeration k: the drawn heights are k times the archive's (the camera is in that space).
    const double k = settings.exaggeration;
    const HeightQuantization& quantization = reader_.quantization();
    glProgramUniform1f(id, program.uniform("u_height_scale"), float(k * quantization.scale));
    glProgramUniform1f(id, program.uniform("u_height_offset"),
                       float(k * quantization.offset - camera.position().z));
    glProgramUniform1f(id, program.uniform("u_exaggeration"), float(k));
    glProgramUniform1i(id, program.uniform("u_patch_cells"), reader_.geometry().patchSize() - 1);
    glProgramUniform1i(id, program.uniform("u_block_cells"), reader_.blockLayout().block_cells);
}

void FrameUniforms::setShading(const gpu::ShaderProgram& program, const lod::Camera& camera,
                               const RenderSettings& settings) const
{
    const GLuint id = program.id();
    const glm::dvec3 sun = glm::normalize(settings.sun_direction);
    glProgramUniform3f(id, program.uniform("u_sun_direction"), float(sun.x), float(sun.y),
                       float(sun.z));
    const double k = settings.exaggeration;
    glProgramUniform2f(id, program.uniform("u_height_range"),
                       float(k * min_height_ - camera.position().z),
                       float(k * max_height_ - camera.position().z));
    glProgramUniform1f(id, program.uniform("u_sea_level"), float(-camera.position().z));
    // Archives before format v4 store no water: the palette's old rule, heights <= 0 m.
    glProgramUniform1i(id, program.uniform("u_water_from_height"),
                       reader_.storesSampleFlags() ? 0 : 1);
    // Fog fades to the sky's horizon and thickens over the terrain's own size: a tenth of the
    // light lost across it.
    const double extent = std::max(quadtree_.frame().extentX(), quadtree_.frame().extentY());
    glProgramUniform3f(id, program.uniform("u_fog_colour"), kHorizonColour.r, kHorizonColour.g,
                       kHorizonColour.b);
    glProgramUniform1f(id, program.uniform("u_fog_density"),
                       settings.fog ? float(0.105 / std::max(extent, 1.0)) : 0.f);
    glProgramUniform1i(id, program.uniform("u_block_cells_f"), reader_.blockLayout().block_cells);
    glProgramUniform3f(id, program.uniform("u_flat_colour"), 0.05f, 0.05f, 0.08f);
    setPaletteUniforms(program);
}

} // namespace ridge::render
