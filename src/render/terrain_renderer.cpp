#include "ridge/render/terrain_renderer.h"

#include "instance_buffer.h"
#include "palette_uniforms.h"
#include "patch_textures.h"
#include "resident_set.h"
#include "scheme_plan.h"
#include "surface_capture.h"
#include "terrain_scheme.h"

#include "ridge/core/error.h"
#include "ridge/gpu/gl_objects.h"
#include "ridge/gpu/gpu_timer.h"
#include "ridge/gpu/primitive_counter.h"
#include "ridge/gpu/shader_program.h"
#include "ridge/lod/coarse_terrain.h"
#include "ridge/lod/edge_tessellation.h"
#include "ridge/lod/screen_space_error.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_inverse.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>

namespace ridge::render {
namespace {

double millisecondsSince(std::chrono::steady_clock::time_point t0)
{
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

} // namespace

glm::dmat4 reverseZProjection(const lod::Camera& camera)
{
    const double f = 1.0 / std::tan(camera.fovY() * 0.5);
    const double aspect = double(camera.viewport().width) / camera.viewport().height;
    glm::dmat4 p(0.0);
    p[0][0] = f / aspect;
    p[1][1] = f;
    p[2][3] = -1.0;
    p[3][2] = camera.nearPlane();
    return p;
}

namespace {

void setMatrix(const gpu::ShaderProgram& program, const char* name, const glm::dmat4& m)
{
    const glm::mat4 f(m);
    glProgramUniformMatrix4fv(program.id(), program.uniform(name), 1, GL_FALSE, glm::value_ptr(f));
}

} // namespace

struct TerrainRenderer::Impl {
    const archive::ArchiveReader& reader;
    RendererOptions options;
    SchemePlan plan;
    lod::PatchQuadtree quadtree;
    int slots = 0; // texture-array layers
    ResidentSet resident;
    TessellationBlockLayout layout;
    HeightQuantization quantization;
    int n = 0;                                // samples per patch side
    int blocks_per_side = 0;                  // B
    int block_levels = 0;                     // D
    float min_height = 0.f, max_height = 0.f; // terrain frame, metres
    // The level-0 patch on the CPU: ground heights and clip planes for cameras.
    std::optional<lod::CoarseTerrain> coarse;
    std::vector<PatchId> last_drawn;
    // What the last draw() drew, for lastFrameSurface() (picking): replayed, not re-selected.
    struct LastFrame {
        lod::Camera camera, lod_camera;
        RenderSettings settings; // with the ε met
        PatchInstances instances;
        TerrainScheme* scheme = nullptr;
    };
    std::optional<LastFrame> last_frame;
    InstanceBuffer instances;
    SurfaceCapture surface_capture;
    gpu::GlVertexArray empty_vao;
    // The drawable schemes, each over the shared pieces above.
    std::unique_ptr<Schemes> schemes;
    gpu::ShaderProgram sky_program;
    gpu::GpuTimer timer;                              // terrain pass
    gpu::GpuTimer upload_timer;                       // uploads and normal maps of new patches
    gpu::PrimitiveCounter triangles;                  // terrain pass

    Impl(const archive::ArchiveReader& r, const RendererOptions& o);
    // The scheme `settings` names, constructed on first use; throws when this renderer was
    // not built for it.
    TerrainScheme& schemeFor(const RenderSettings& settings) const;
    // Selection, residency and instance buffer for one frame; `used` receives `settings` with
    // the ε actually met (raised when the selection exceeded the slots), which the
    // tessellator must use too.
    PatchInstances beginFrame(const lod::Camera& camera, const lod::Camera& lod_camera,
                              const RenderSettings& settings, FrameStats& stats,
                              RenderSettings& used, bool frozen = false)
    {
        const lod::Selection selection = prepare(lod_camera, settings, stats, frozen);
        used = settings;
        used.epsilon_px = selection.epsilon_px;
        return instances.write(schemeFor(used), camera, lod_camera, selection, used);
    }
    void setFrameUniforms(const gpu::ShaderProgram& program, const SchemeFrame& frame);
    // The triangles of frame.instances (already in the instance buffer) drawn as `frame`.
    CapturedSurface captureInstances(TerrainScheme& scheme, const SchemeFrame& frame)
    {
        return surface_capture.capture(
            scheme, frame, [&](const gpu::ShaderProgram& p) { setFrameUniforms(p, frame); });
    }
    // `frozen`: draw what is resident (resident cover), changing nothing.
    lod::Selection prepare(const lod::Camera& camera, const RenderSettings& settings,
                           FrameStats& stats, bool frozen = false);
};

TerrainRenderer::Impl::Impl(const archive::ArchiveReader& r, const RendererOptions& o)
    : reader(r), options(o), plan(planSchemes(r, o)), quadtree(lod::PatchQuadtree::fromArchive(r)),
      slots(PatchTextures::slotCount(r, plan.slot_bytes, o.vram_budget_mb,
                                     o.max_resident_patches)),
      resident(r, quadtree, options, slots, plan), layout(r.blockLayout()),
      quantization(r.quantization()), instances(quadtree, resident.residency())
{
    n = reader.geometry().patchSize();
    blocks_per_side = layout.blocksPerSide();
    block_levels = std::min(layout.levels(), lod::kMaxBlockLevels);
    const lod::PatchBounds& root = quadtree.bounds(PatchId{0, 0, 0});
    min_height = root.min_height;
    max_height = root.max_height;
    coarse.emplace(quadtree.frame(), quadtree.box(PatchId{0, 0, 0}),
                   resident.load(PatchId{0, 0, 0})->codes, quantization);
    schemes = std::make_unique<Schemes>(
        plan, SchemeResources{reader, quadtree, options, resident.textures(),
                              resident.residency(), slots, -1});
    resident.start(*schemes);
    sky_program =
        gpu::ShaderProgram({{GL_VERTEX_SHADER, "sky.vert"}, {GL_FRAGMENT_SHADER, "sky.frag"}});
}

TerrainScheme& TerrainRenderer::Impl::schemeFor(const RenderSettings& settings) const
{
    return schemes->get(settings.scheme);
}

void TerrainRenderer::Impl::setFrameUniforms(const gpu::ShaderProgram& program,
                                             const SchemeFrame& frame)
{
    const lod::Camera& camera = frame.camera;
    const RenderSettings& settings = frame.settings;
    const GLuint id = program.id();
    setMatrix(program, "u_view_projection", reverseZProjection(camera) * camera.view());
    // LOD is decided for frame.lod_camera: positions relative to the drawn camera, moved to
    // the LOD camera and projected by it (the same matrix when both are one camera).
    const glm::dmat4 to_lod_camera = glm::translate(glm::dmat4(1.0), camera.position() -
                                                                         frame.lod_camera.position());
    setMatrix(program, "u_lod_view_projection",
              reverseZProjection(frame.lod_camera) * frame.lod_camera.view() * to_lod_camera);
    const glm::dvec3 lod_offset = frame.lod_camera.position() - camera.position();
    glProgramUniform3f(id, program.uniform("u_lod_camera"), float(lod_offset.x),
                       float(lod_offset.y), float(lod_offset.z));
    const CameraAnchor anchor = cameraAnchor(quadtree.frame(), camera.position());
    glProgramUniform2f(id, program.uniform("u_spacing"), float(quadtree.frame().spacingX()),
                       float(-quadtree.frame().spacingY()));
    glProgramUniform2f(id, program.uniform("u_anchor_offset"), float(anchor.x_rel),
                       float(anchor.y_rel));
    glProgramUniform2f(id, program.uniform("u_viewport"), float(camera.viewport().width),
                       float(camera.viewport().height));
    glProgramUniform1f(id, program.uniform("u_epsilon"), float(settings.epsilon_px));
    // Exaggeration k: the drawn heights are k times the archive's (the camera is in that space).
    const double k = settings.exaggeration;
    glProgramUniform1f(id, program.uniform("u_height_scale"), float(k * quantization.scale));
    glProgramUniform1f(id, program.uniform("u_height_offset"),
                       float(k * quantization.offset - camera.position().z));
    glProgramUniform1f(id, program.uniform("u_exaggeration"), float(k));
    glProgramUniform1i(id, program.uniform("u_patch_cells"), n - 1);
    glProgramUniform1i(id, program.uniform("u_block_cells"), layout.block_cells);
    glProgramUniform1i(id, program.uniform("u_blocks_per_side"), blocks_per_side);
    glProgramUniform1i(id, program.uniform("u_block_levels"), block_levels);
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
        // Widened beyond float rounding of camera-relative positions (~1e-7 of the distance):
        // a visible block must never be culled.
        planes[i][3] = float(d + 0.01 + 1e-6 * camera.farPlane());
    }
    glProgramUniform4fv(id, program.uniform("u_frustum"), 6, &planes[0][0]);
    instances.bind();
    resident.textures().bind();
    schemeFor(settings).setUniforms(program, frame);
}

lod::Selection TerrainRenderer::Impl::prepare(const lod::Camera& camera,
                                              const RenderSettings& settings, FrameStats& stats,
                                              bool frozen)
{
    resident.textures().collect(); // λ maxima derived on the GPU in earlier frames
    auto t0 = std::chrono::steady_clock::now();
    lod::SelectionSettings ss;
    ss.epsilon_px = settings.epsilon_px;
    ss.texel_px = settings.texel_px;
    ss.cull = settings.cull;
    ss.max_patches = size_t(slots);
    ss.side_on = settings.side_on_bound;
    ss.exaggeration = settings.exaggeration;
    schemeFor(settings).adjustSelection(settings, ss);
    lod::Selection selection = quadtree.select(camera, ss);
    stats.cpu_select_ms = millisecondsSince(t0);
    stats.patches = int(selection.patches.size());
    stats.culled = selection.culled;
    stats.epsilon_px = selection.epsilon_px;
    stats.texel_px = selection.texel_px;
    stats.coarser = selection.epsilon_px > ss.epsilon_px;
    t0 = std::chrono::steady_clock::now();
    if (frozen)
        return resident.frozenCover(std::move(selection));
    upload_timer.begin();
    try {
        if (resident.streaming())
            selection = resident.stream(selection, camera, ss, stats);
        else
            resident.makeResident(selection, stats);
    } catch (...) {
        upload_timer.end(); // keep begin/end balanced for the next frame
        throw;
    }
    upload_timer.end();
    stats.gpu_upload_ms = options.synchronous_stats ? upload_timer.waitMs() : upload_timer.lastMs();
    stats.cpu_load_ms = millisecondsSince(t0);
    resident.countTraffic(stats);
    stats.patches = int(selection.patches.size());
    last_drawn.clear();
    for (const lod::SelectedPatch& p : selection.patches)
        last_drawn.push_back(p.id);
    return selection;
}

namespace {

// Checked before Impl touches GL or sizes anything from them.
const RendererOptions& validated(const RendererOptions& options)
{
    options.validate();
    return options;
}

} // namespace

TerrainRenderer::TerrainRenderer(const archive::ArchiveReader& reader,
                                 const RendererOptions& options)
    : impl_(std::make_unique<Impl>(reader, validated(options)))
{
}

TerrainRenderer::~TerrainRenderer() = default;

const lod::PatchQuadtree& TerrainRenderer::quadtree() const
{
    return impl_->quadtree;
}

int TerrainRenderer::blockCells() const { return impl_->layout.block_cells; }

const std::vector<std::string>& TerrainRenderer::schemes() const
{
    return impl_->plan.names;
}

int TerrainRenderer::residentSlots() const
{
    return impl_->slots;
}

const std::vector<PatchId>& TerrainRenderer::lastDrawnPatches() const
{
    return impl_->last_drawn;
}

void TerrainRenderer::waitForStreaming()
{
    impl_->resident.waitIdle();
}

bool TerrainRenderer::waitForStreaming(double timeout_seconds)
{
    // A billion seconds (32 years) keeps the deadline within the clock's range.
    checkParameter("streaming wait timeout (s)", timeout_seconds, ValueRange::closed(0.0, 1e9));
    return impl_->resident.waitIdleFor(timeout_seconds);
}

std::string TerrainRenderer::streamingError() const
{
    return impl_->resident.error();
}

uint64_t TerrainRenderer::cacheMisses() const
{
    return impl_->resident.cacheMisses();
}

uint64_t TerrainRenderer::cacheHits() const
{
    return impl_->resident.cacheHits();
}

std::vector<uint16_t> TerrainRenderer::residentCodes(PatchId p) const
{
    const int slot = impl_->resident.residency().slotOf(p);
    return slot < 0 ? std::vector<uint16_t>() : impl_->resident.textures().readCodes(slot);
}

std::vector<float> TerrainRenderer::residentBlockErrors(PatchId p) const
{
    const int slot = impl_->resident.residency().slotOf(p);
    return slot < 0 ? std::vector<float>() : impl_->resident.textures().readBlockErrors(slot);
}

std::vector<int8_t> TerrainRenderer::residentNormals(PatchId p) const
{
    const int slot = impl_->resident.residency().slotOf(p);
    return slot < 0 ? std::vector<int8_t>() : impl_->resident.textures().readNormals(slot);
}

double TerrainRenderer::residentLambdaMax(PatchId p) const
{
    const int slot = impl_->resident.residency().slotOf(p);
    return slot < 0 ? -1.0 : double(impl_->resident.textures().lambdaMax(slot));
}

size_t TerrainRenderer::streamingCacheBytes() const
{
    return impl_->resident.cacheBytes();
}

FrameStats TerrainRenderer::draw(const lod::Camera& camera, const RenderSettings& settings,
                                 const lod::Camera* lod_camera, const HostProjection* host)
{
    settings.validate();
    Impl& m = *impl_;
    TerrainScheme& scheme = m.schemeFor(settings);
    const lod::Camera& lod = lod_camera ? *lod_camera : camera;
    FrameStats stats;
    RenderSettings s;
    PatchInstances ranges = m.beginFrame(camera, lod, settings, stats, s);
    const SchemeFrame frame{camera, lod, s, ranges};
    stats.bytes_uploaded += scheme.beginDraw(frame);

    // ridge's own frame is reverse-Z; a host's is whatever its projection and convention are.
    const bool greater = !host || host->greater;
    glClipControl(GL_LOWER_LEFT, !host || host->zero_to_one ? GL_ZERO_TO_ONE : GL_NEGATIVE_ONE_TO_ONE);
    glDepthMask(GL_TRUE);
    if (s.clear) {
        glClearColor(s.clear_colour.r, s.clear_colour.g, s.clear_colour.b, s.clear_colour.a);
        glClearDepth(greater ? 0.0 : 1.0);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    }
    glDisable(GL_CULL_FACE);

    const glm::vec3 horizon(0.78f, 0.84f, 0.90f), zenith(0.30f, 0.48f, 0.75f);
    const glm::dmat4 view_projection =
        host ? host->view_projection : reverseZProjection(camera) * camera.view();
    if (s.sky && s.clear) {
        // Background only: no depth written, the cleared depth stays the far value.
        glDisable(GL_DEPTH_TEST);
        glDepthMask(GL_FALSE);
        m.sky_program.use();
        setMatrix(m.sky_program, "u_inverse_view_projection", glm::inverse(view_projection));
        glUniform3f(m.sky_program.uniform("u_horizon_colour"), horizon.r, horizon.g, horizon.b);
        glUniform3f(m.sky_program.uniform("u_zenith_colour"), zenith.r, zenith.g, zenith.b);
        glBindVertexArray(m.empty_vao.id());
        glDrawArrays(GL_TRIANGLES, 0, 3);
        glDepthMask(GL_TRUE);
    }

    glEnable(GL_DEPTH_TEST);
    glDepthFunc(greater ? GL_GREATER : GL_LESS);
    const glm::dvec3 sun = glm::normalize(s.sun_direction);
    // Fog thickens over the terrain's own size: a tenth of the light lost across it.
    const double extent = std::max(m.quadtree.frame().extentX(), m.quadtree.frame().extentY());
    for (const gpu::ShaderProgram* p : scheme.programs(false)) {
        const GLuint id = p->id();
        m.setFrameUniforms(*p, frame);
        if (host) // the image from the host's matrices; LOD (u_lod_view_projection) from `lod`
            setMatrix(*p, "u_view_projection", view_projection);
        glProgramUniform3f(id, p->uniform("u_sun_direction"), float(sun.x), float(sun.y),
                           float(sun.z));
        glProgramUniform2f(id, p->uniform("u_height_range"),
                           float(s.exaggeration * m.min_height - camera.position().z),
                           float(s.exaggeration * m.max_height - camera.position().z));
        glProgramUniform1f(id, p->uniform("u_sea_level"), float(-camera.position().z));
        // Archives before format v4 store no water: the palette's old rule, heights <= 0 m.
        glProgramUniform1i(id, p->uniform("u_water_from_height"),
                           m.reader.storesSampleFlags() ? 0 : 1);
        glProgramUniform3f(id, p->uniform("u_fog_colour"), horizon.r, horizon.g, horizon.b);
        glProgramUniform1f(id, p->uniform("u_fog_density"),
                           s.fog ? float(0.105 / std::max(extent, 1.0)) : 0.f);
        glProgramUniform1i(id, p->uniform("u_block_cells_f"), m.layout.block_cells);
        glProgramUniform3f(id, p->uniform("u_flat_colour"), 0.05f, 0.05f, 0.08f);
        setPaletteUniforms(*p);
    }
    // Both instance groups with `mode` (3: the wireframe's flat colour).
    auto drawTerrain = [&](int mode) {
        forEachGroup(scheme.programs(false), ranges,
                     [&](const gpu::ShaderProgram& p, size_t first, size_t n) {
                         p.use();
                         glUniform1i(p.uniform("u_mode"), mode);
                         scheme.draw(p, frame, first, n);
                     });
    };

    m.timer.begin();
    m.triangles.begin();
    drawTerrain(int(s.mode));
    m.triangles.end();
    if (s.wireframe && ranges.total()) {
        glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
        glEnable(GL_POLYGON_OFFSET_LINE);
        // Lines pulled towards the eye: larger depth is nearer in reverse-Z, smaller otherwise.
        glPolygonOffset(greater ? 1.f : -1.f, greater ? 1.f : -1.f);
        glDepthFunc(greater ? GL_GEQUAL : GL_LEQUAL);
        drawTerrain(3);
        glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
        glDisable(GL_POLYGON_OFFSET_LINE);
    }
    m.timer.end();
    const bool synchronous = m.options.synchronous_stats;
    stats.triangles = synchronous ? m.triangles.wait() : m.triangles.latest();
    stats.gpu_ms = synchronous ? m.timer.waitMs() : m.timer.lastMs();

    // Leave the default GL conventions to whatever draws next (an overlay, a test).
    glDepthFunc(GL_LESS);
    glClearDepth(1.0);
    glClipControl(GL_LOWER_LEFT, GL_NEGATIVE_ONE_TO_ONE);
    gpu::checkGlError("terrain renderer: draw");
    m.last_frame = Impl::LastFrame{camera, lod, s, std::move(ranges), &scheme};
    return stats;
}

CapturedSurface TerrainRenderer::lastFrameSurface()
{
    Impl& m = *impl_;
    if (!m.last_frame)
        return {};
    Impl::LastFrame& f = *m.last_frame;
    const SchemeFrame frame{f.camera, f.lod_camera, f.settings, f.instances};
    return m.captureInstances(*f.scheme, frame);
}


CapturedSurface TerrainRenderer::capture(const lod::Camera& camera, const RenderSettings& settings,
                                         const lod::Camera* lod_camera, bool keep_residency)
{
    settings.validate();
    Impl& m = *impl_;
    TerrainScheme& scheme = m.schemeFor(settings);
    const lod::Camera& lod = lod_camera ? *lod_camera : camera;
    FrameStats stats;
    RenderSettings s;
    m.last_frame.reset(); // the instance buffer is this capture's now
    const PatchInstances ranges = m.beginFrame(camera, lod, settings, stats, s, keep_residency);
    const SchemeFrame frame{camera, lod, s, ranges};
    return m.captureInstances(scheme, frame);
}

double TerrainRenderer::groundHeight(double x, double y, double exaggeration) const
{
    checkParameter("exaggeration", exaggeration, RenderSettings::kExaggerationRange);
    return exaggeration * impl_->coarse->groundHeight(x, y);
}

void TerrainRenderer::clipPlanesFor(glm::dvec3 position, double& near_m, double& far_m,
                                    double exaggeration) const
{
    if (exaggeration == 1.0)
        return impl_->coarse->clipPlanesFor(position, near_m, far_m);
    impl_->coarse->exaggerated(exaggeration).clipPlanesFor(position, near_m, far_m);
}

lod::Camera TerrainRenderer::defaultCamera(lod::Viewport viewport, double fov_y_degrees,
                                           double exaggeration) const
{
    if (exaggeration == 1.0)
        return impl_->coarse->defaultCamera(viewport, fov_y_degrees);
    return impl_->coarse->exaggerated(exaggeration).defaultCamera(viewport, fov_y_degrees);
}

} // namespace ridge::render
