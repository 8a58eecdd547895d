#include "frame_uniforms.h"

#include "palette_uniforms.h"
#include "patch_instances.h"
#include "sky.h"

#include <glm/geometric.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>

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
    if (const lod::ProjectedGrid* grid = quadtree.frame().projectedGrid())
        lattice_ = std::make_unique<ProjectedLattice>(*grid);
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
    setSurface(program, anchor);
    // Exaggeration k: the drawn heights are k times the archive's (the camera is in that space).
    const double k = settings.exaggeration;
    const HeightQuantization& quantization = reader_.quantization();
    glProgramUniform1f(id, program.uniform("u_height_scale"), float(k * quantization.scale));
    glProgramUniform1f(id, program.uniform("u_height_offset"),
                       float(k * quantization.offset - anchor.height));
    glProgramUniform1f(id, program.uniform("u_exaggeration"), float(k));
    glProgramUniform1i(id, program.uniform("u_patch_cells"), reader_.geometry().patchSize() - 1);
    glProgramUniform1f(id, program.uniform("u_unclipped_extent"),
                       float(reader_.geometry().patchSize() - 1));
    glProgramUniform2i(id, program.uniform("u_drop_beyond"), 0, 0);
    glProgramUniform1i(id, program.uniform("u_block_cells"), reader_.blockLayout().block_cells);
}

void FrameUniforms::setSurface(const gpu::ShaderProgram& program, const CameraAnchor& anchor) const
{
    const GLuint id = program.id();
    const lod::TerrainFrame& frame = quadtree_.frame();
    if (!frame.onEllipsoid())
        return;
    // Everything of Earth scale is formed here in double; the GPU adds offsets to it.
    const lod::GeodeticGrid& g = frame.geodetic();
    const double e2 = g.ellipsoid.e2();
    const glm::dvec3 c = anchor.camera;
    glProgramUniform3f(id, program.uniform("u_camera_world"), float(c.x), float(c.y), float(c.z));
    glProgramUniform1f(id, program.uniform("u_polar_ratio"), float(1.0 / (1.0 - e2)));
    glProgramUniform1f(id, program.uniform("u_bulge_per_rad2"),
                       float(1.01 * g.ellipsoid.maxCurvatureRadius() / 8.0));
    glProgramUniform2f(id, program.uniform("u_angle_step"), float(frame.columnAngle()),
                       float(frame.projectedGrid() ? frame.rowAngle() : g.dlat));
    glProgramUniform2i(id, program.uniform("u_pole_rows"), -1, -1);
    glProgramUniform1i(id, program.uniform("u_wrap_columns"), int(g.wrap_columns));
    glProgramUniform2i(id, program.uniform("u_anchor_sample"), int(anchor.column), int(anchor.row));
    if (lattice_) {
        lattice_->set(program, anchor);
        return;
    }
    const double lat = anchor.latitude, lon = anchor.longitude;
    const double w = 1.0 - e2 * std::sin(lat) * std::sin(lat);
    const double n = g.ellipsoid.a / std::sqrt(w);
    glProgramUniform4f(id, program.uniform("u_anchor_trig"), float(std::cos(lat)),
                       float(std::sin(lat)), float(std::cos(lon)), float(std::sin(lon)));
    glProgramUniform2f(id, program.uniform("u_anchor_fraction"), float(anchor.column_fraction),
                       float(anchor.row_fraction));
    glProgramUniform4f(id, program.uniform("u_anchor_radii"), float(n + anchor.height),
                       float(n * (1.0 - e2) + anchor.height), float(std::sqrt(w)), float(e2));
    glProgramUniform1f(id, program.uniform("u_semi_major"), float(g.ellipsoid.a));
    const int last = frame.geometry().height() - 1;
    glProgramUniform2i(id, program.uniform("u_pole_rows"),
                       frame.poleRow(0.0) ? (g.dlat < 0 ? 0 : last) : -1,
                       frame.poleRow(double(last)) ? (g.dlat < 0 ? last : 0) : -1);
}

void FrameUniforms::setShading(const gpu::ShaderProgram& program, const lod::Camera& camera,
                               const RenderSettings& settings) const
{
    const GLuint id = program.id();
    const lod::TerrainFrame& frame = quadtree_.frame();
    glm::dvec3 sun = glm::normalize(settings.sun_direction);
    const double reference = frame.referenceHeight(camera.position());
    if (frame.onEllipsoid()) {
        // The sun is given in the local frame (east, north, up) under the camera and is
        // that direction everywhere (at infinity): ECEF here, like the fragments' normals.
        const glm::dvec3 g = frame.gridOf(camera.position());
        sun = glm::normalize(frame.basisAt(g.x, g.y).matrix() * sun);
    }
    glProgramUniform3f(id, program.uniform("u_sun_direction"), float(sun.x), float(sun.y),
                       float(sun.z));
    const double k = settings.exaggeration;
    glProgramUniform2f(id, program.uniform("u_height_range"), float(k * min_height_ - reference),
                       float(k * max_height_ - reference));
    glProgramUniform1f(id, program.uniform("u_sea_level"), float(-reference));
    // Fog fades to the sky's horizon. On a plane it thickens over the terrain's own size: a
    // tenth of the light lost across it. On the globe it is the air's: densest at sea level
    // (a 150 km visibility, 1/e) and thinning with altitude over the scale height, so the
    // Earth seen from orbit keeps a faint haze that thickens towards the limb, and a low view
    // fades into the distance.
    const double extent = std::max(quadtree_.frame().extentX(), quadtree_.frame().extentY());
    const double density =
        frame.onEllipsoid() ? kSeaLevelFogPerMetre : 0.105 / std::max(extent, 1.0);
    glProgramUniform3f(id, program.uniform("u_fog_colour"), kHorizonColour.r, kHorizonColour.g,
                       kHorizonColour.b);
    glProgramUniform1f(id, program.uniform("u_fog_density"), settings.fog ? float(density) : 0.f);
    glProgramUniform1f(id, program.uniform("u_fog_scale_height"),
                       frame.onEllipsoid() ? float(kAirScaleHeightMetres) : 0.f);
    glProgramUniform1i(id, program.uniform("u_block_cells_f"), reader_.blockLayout().block_cells);
    glProgramUniform3f(id, program.uniform("u_flat_colour"), 0.05f, 0.05f, 0.08f);
    setPaletteUniforms(program);
}

} // namespace ridge::render
