#include "ridge/render/terrain_renderer.h"

#include "frame_uniforms.h"
#include "instance_buffer.h"
#include "patch_textures.h"
#include "popping_raster.h"
#include "resident_set.h"
#include "scheme_plan.h"
#include "shading_map.h"
#include "sky.h"
#include "surface_capture.h"
#include "terrain_scheme.h"

#include "ridge/core/error.h"
#include "ridge/gpu/gl_objects.h"
#include "ridge/gpu/gpu_timer.h"
#include "ridge/gpu/primitive_counter.h"
#include "ridge/gpu/shader_program.h"
#include "ridge/lod/coarse_terrain.h"
#include "ridge/lod/screen_space_error.h"
#include "ridge/render/frame_measures.h"

#include <chrono>
#include <cmath>
#include <memory>
#include <optional>
#include <utility>

namespace ridge::render {
namespace {

const SchemeOptions kSharedOnly; // SchemeResources' `own` before Schemes gives each its own

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

// A frame: select (the scheme adjusts the selection) → make the selection resident (synchronous
// or streamed: ResidentSet) → instance records (InstanceBuffer) → uniforms (FrameUniforms and
// the scheme's) → sky, the scheme's draws per instance group, counted and timed. capture()
// runs the same frame through transform feedback (SurfaceCapture).
struct TerrainRenderer::Impl {
    const archive::ArchiveReader& reader;
    RendererOptions options;
    // Formed once (a projected grid's lattice samples PROJ): the plan and the quadtree share it.
    lod::TerrainFrame frame;
    SchemePlan plan;
    lod::PatchQuadtree quadtree;
    int slots = 0; // texture-array layers
    ResidentSet resident;
    // The level-0 patch on the CPU: ground heights and clip planes for cameras.
    lod::CoarseTerrain coarse;
    // The drawable schemes, each over the resident set's textures and residency.
    Schemes schemes;
    // The screen-space-error walk, for schemes that do not select for themselves.
    lod::QuadtreeSelector quadtree_selector{quadtree};
    InstanceBuffer instances;
    // Where drawn patches' fragments shade from: finer resident patches (texture detail).
    ShadingMap shading_map;
    // Streaming arrivals fading in over the ancestors that stood in for them.
    lod::ArrivalBlends arrivals;
    FrameUniforms uniforms;
    SurfaceCapture surface_capture;
    // measureFramePopping's last surface: on the GPU (plane frames; made on first use), or
    // its heights on the CPU (the ellipsoid).
    std::unique_ptr<PoppingRaster> popping_raster;
    std::optional<SampleHeights> popping_previous;
    std::vector<PatchId> last_drawn;
    // What the last draw() drew, for lastFrameSurface() (picking): replayed, not re-selected.
    struct LastFrame {
        lod::Camera camera, lod_camera;
        RenderSettings settings; // with the ε met
        PatchInstances instances;
        TerrainScheme* scheme = nullptr;
    };
    std::optional<LastFrame> last_frame;
    Sky sky;
    gpu::GpuTimer timer;             // terrain pass
    gpu::GpuTimer upload_timer;      // uploads and normal maps of new patches
    gpu::PrimitiveCounter triangles; // terrain pass

    Impl(const archive::ArchiveReader& r, const RendererOptions& o);
    // Selection, residency and instance buffer for one frame of `scheme`; `used` receives
    // `settings` with the ε actually met (raised when the selection exceeded the slots), which
    // the tessellator must use too.
    PatchInstances beginFrame(TerrainScheme& scheme, const lod::Camera& camera,
                              const lod::Camera& lod_camera, const RenderSettings& settings,
                              FrameStats& stats, RenderSettings& used, bool frozen = false)
    {
        const lod::Selection selection = prepare(scheme, lod_camera, settings, stats, frozen);
        used = settings;
        used.epsilon_px = selection.epsilon_px;
        stats.bytes_uploaded += shading_map.update(selection.patches, resident.residency(),
                                                   quadtree.geometry(), settings.texel_px > 0.0);
        return instances.write(scheme, camera, lod_camera, selection, used,
                               fadesArrivals(settings.scheme) ? &arrivals : nullptr);
    }
    bool fadesArrivals(const std::string& scheme) const
    {
        return resident.streaming() && options.arrival_blend.max_frames > 0 &&
               lodSchemePromises(scheme).arrivals != SchemePromises::Arrivals::Replace;
    }
    // The fades of this streaming frame's arrivals (`wanted`: the selection, `drawn`: its
    // resident cover), each as long as its jump on screen asks.
    void advanceArrivals(const lod::Camera& camera, const lod::SelectionSettings& ss,
                         const lod::Selection& wanted, const lod::Selection& drawn);
    // `frozen`: draw what is resident (resident cover), changing nothing.
    lod::Selection prepare(TerrainScheme& scheme, const lod::Camera& camera,
                           const RenderSettings& settings, FrameStats& stats, bool frozen);
    // The frame's uniforms of one of `scheme`'s programs, its instances and textures bound.
    void setUniforms(TerrainScheme& scheme, const gpu::ShaderProgram& program,
                     const SchemeFrame& frame)
    {
        uniforms.setGeometry(program, frame.camera, frame.settings);
        instances.bind();
        resident.textures().bind();
        shading_map.bind();
        glProgramUniform1i(program.id(), program.uniform("u_shading_detail"),
                           frame.settings.texel_px > 0.0);
        scheme.setUniforms(program, frame);
    }
    // The triangles of frame.instances (already in the instance buffer) drawn as `frame`.
    CapturedSurface captureInstances(TerrainScheme& scheme, const SchemeFrame& frame)
    {
        return surface_capture.capture(
            scheme, frame, [&](const gpu::ShaderProgram& p) { setUniforms(scheme, p, frame); });
    }
    // capture()'s frame (the instance buffer is the capture's from then on) handed to `use`
    // with its scheme: TerrainRenderer::capture and the popping metric.
    template <class Use>
    auto withCaptureFrame(const lod::Camera& camera, const RenderSettings& settings,
                          const lod::Camera* lod_camera, bool keep_residency, Use&& use)
    {
        settings.validate();
        TerrainScheme& scheme = schemes.get(settings.scheme);
        const lod::Camera& lod = lod_camera ? *lod_camera : camera;
        FrameStats stats;
        RenderSettings s;
        last_frame.reset();
        const PatchInstances ranges =
            beginFrame(scheme, camera, lod, settings, stats, s, keep_residency);
        return use(scheme, SchemeFrame{camera, lod, s, ranges});
    }
    // The frame's triangles left in the capture's feedback buffer; returns their vertices.
    size_t recordInstances(TerrainScheme& scheme, const SchemeFrame& frame)
    {
        return surface_capture.record(
            scheme, frame, [&](const gpu::ShaderProgram& p) { setUniforms(scheme, p, frame); });
    }
};

TerrainRenderer::Impl::Impl(const archive::ArchiveReader& r, const RendererOptions& o)
    : reader(r), options(o), frame(lod::terrainFrameOf(r, o.frame, r.path())),
      plan(planSchemes(r, frame, options)), quadtree(lod::PatchQuadtree::fromArchive(r, frame)),
      slots(PatchTextures::slotCount(
          r, plan.slot_bytes, options.vram_budget_mb, options.max_resident_patches,
          ResidentSet::gpuDecodedCodec(r, options, plan), plan.fixed_bytes)),
      resident(r, quadtree, options, slots, plan),
      coarse(quadtree.frame(), quadtree.bounds(PatchId{0, 0, 0}).min_height,
             quadtree.bounds(PatchId{0, 0, 0}).max_height, resident.load(PatchId{0, 0, 0})->codes,
             r.quantization()),
      // The shared pieces; each scheme gets its own options and product (Schemes::get).
      schemes(plan, SchemeResources{r, quadtree, options, kSharedOnly, resident.textures(),
                                    resident.residency(), slots, -1}),
      instances(quadtree, resident.residency()), shading_map(slots),
      arrivals(options.arrival_blend), uniforms(r, quadtree)
{
    resident.start(schemes);
}

lod::Selection TerrainRenderer::Impl::prepare(TerrainScheme& scheme, const lod::Camera& camera,
                                              const RenderSettings& settings, FrameStats& stats,
                                              bool frozen)
{
    if (const lod::TerrainFrame& f = quadtree.frame();
        f.onEllipsoid() && f.geodetic().wrap_columns > 0 &&
        !lodSchemePromises(settings.scheme).wrapping_globe)
        throw Error("the " + settings.scheme +
                    " scheme cannot draw a globe that goes round the Earth yet (" + reader.path() +
                    "): choose another --lod, or --frame plane");
    resident.textures().collect(); // λ maxima derived on the GPU in earlier frames
    auto t0 = std::chrono::steady_clock::now();
    lod::SelectionSettings ss;
    ss.epsilon_px = settings.epsilon_px;
    ss.texel_px = settings.texel_px;
    ss.cull = settings.cull;
    ss.max_patches = size_t(slots);
    ss.side_on = settings.side_on_bound;
    ss.exaggeration = settings.exaggeration;
    scheme.adjustSelection(settings, ss);
    // The scheme's own selector (rings), or the screen-space-error walk.
    lod::PatchSelector& selector = scheme.selector() ? *scheme.selector() : quadtree_selector;
    lod::Selection selection;
    selector.select(camera, ss, selection);
    stats.cpu_select_ms = millisecondsSince(t0);
    stats.patches = int(selection.patches.size());
    stats.culled = selection.culled;
    stats.epsilon_px = selection.epsilon_px;
    stats.texel_px = selection.texel_px;
    stats.coarser = selection.epsilon_px > ss.epsilon_px || selection.levels_coarser > 0;
    stats.detail = int(selection.detail.size());
    t0 = std::chrono::steady_clock::now();
    if (frozen)
        return resident.cover(std::move(selection), selector);
    upload_timer.begin();
    try {
        if (resident.streaming()) {
            lod::Selection drawn = resident.stream(selection, selector, camera, ss, stats);
            if (fadesArrivals(settings.scheme)) {
                advanceArrivals(camera, ss, selection, drawn);
                stats.fading = int(arrivals.fading());
            } else {
                arrivals.reset(); // another scheme's frames start none
            }
            drawn.detail.swap(selection.detail); // the drawn cover, with the detail to count
            selection = std::move(drawn);
        } else {
            resident.makeResident(selection, stats);
            selection = resident.cover(std::move(selection), selector); // all of it resident
        }
    } catch (...) {
        upload_timer.end(); // keep begin/end balanced for the next frame
        throw;
    }
    upload_timer.end();
    stats.gpu_upload_ms = options.synchronous_stats ? upload_timer.waitMs() : upload_timer.lastMs();
    stats.cpu_load_ms = millisecondsSince(t0);
    resident.countTraffic(stats);
    stats.patches = int(selection.patches.size());
    for (const lod::SelectedPatch& d : selection.detail)
        stats.detail_resident += resident.residency().slotOf(d.id) >= 0;
    last_drawn.clear();
    for (const lod::SelectedPatch& p : selection.patches)
        last_drawn.push_back(p.id);
    return selection;
}

void TerrainRenderer::Impl::advanceArrivals(const lod::Camera& camera,
                                            const lod::SelectionSettings& ss,
                                            const lod::Selection& wanted,
                                            const lod::Selection& drawn)
{
    const double gamma = lod::screenSpaceErrorFactor(camera);
    const double k = ss.exaggeration;
    arrivals.advance(
        wanted.patches, drawn.patches,
        [&](PatchId p) { return resident.residency().slotOf(p) >= 0; },
        [&](PatchId from, PatchId to) {
            // The two surfaces part by at most Err(A) + Err(P), seen where `to` is nearest.
            const lod::Box box = quadtree.box(to, k);
            const double rho = lod::distanceToBox(camera.position(), box);
            const double err = k * double(quadtree.bounds(from).err + quadtree.bounds(to).err);
            return lod::screen_space_error(gamma, err,
                                           lod::visibleDepthBound(camera, box, rho, ss.side_on));
        });
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

int TerrainRenderer::blockCells() const
{
    return impl_->reader.blockLayout().block_cells;
}

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
    TerrainScheme& scheme = m.schemes.get(settings.scheme);
    const lod::Camera& lod = lod_camera ? *lod_camera : camera;
    FrameStats stats;
    RenderSettings s;
    PatchInstances ranges = m.beginFrame(scheme, camera, lod, settings, stats, s);
    const SchemeFrame frame{camera, lod, s, ranges};
    stats.bytes_uploaded += scheme.beginDraw(frame);
    scheme.addFrameStats(stats);

    // ridge's own frame is reverse-Z; a host's is whatever its projection and convention are.
    const bool greater = !host || host->greater;
    glClipControl(GL_LOWER_LEFT,
                  !host || host->zero_to_one ? GL_ZERO_TO_ONE : GL_NEGATIVE_ONE_TO_ONE);
    glDepthMask(GL_TRUE);
    if (s.clear) {
        glClearColor(s.clear_colour.r, s.clear_colour.g, s.clear_colour.b, s.clear_colour.a);
        glClearDepth(greater ? 0.0 : 1.0);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    }
    glDisable(GL_CULL_FACE);
    const glm::dmat4 view_projection =
        host ? host->view_projection : reverseZProjection(camera) * camera.view();
    if (s.sky && s.clear) {
        const lod::TerrainFrame& f = m.quadtree.frame();
        const glm::dvec3 grid = f.gridOf(camera.position());
        m.sky.draw(view_projection, f.upThrough(camera.position()), f.onEllipsoid() ? grid.z : 0.0);
    }

    glEnable(GL_DEPTH_TEST);
    glDepthFunc(greater ? GL_GREATER : GL_LESS);
    // The uniforms of every program a group is drawn with.
    forEachGroup(scheme, false, frame.settings, ranges,
                 [&](const gpu::ShaderProgram& p, size_t, size_t) {
                     m.setUniforms(scheme, p, frame);
                     if (host) // the image from the host's matrices; LOD from `lod`
                         setMatrix(p, "u_view_projection", view_projection);
                     m.uniforms.setShading(p, camera, s);
                 });
    // The instance groups with `mode` (3: the wireframe's flat colour).
    auto drawTerrain = [&](int mode) {
        forEachGroup(scheme, false, frame.settings, ranges,
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
    Impl& m = *impl_;
    return m.withCaptureFrame(camera, settings, lod_camera, keep_residency,
                              [&](TerrainScheme& scheme, const SchemeFrame& frame) {
                                  return m.captureInstances(scheme, frame);
                              });
}

PoppingReport TerrainRenderer::measureFramePopping(const lod::Camera& camera,
                                                   const RenderSettings& settings)
{
    Impl& m = *impl_;
    // Block culling follows the camera that looks: unculled, a surface is its LOD state's.
    RenderSettings s = settings;
    s.cull_blocks = false;
    const lod::TerrainFrame& f = m.quadtree.frame();
    if (f.onEllipsoid()) {
        SampleHeights now = surfaceHeightsAtSamples(capture(camera, s, nullptr, true), f);
        PoppingReport report;
        if (m.popping_previous)
            report = measurePopping(*m.popping_previous, now, f, camera);
        m.popping_previous = std::move(now);
        return report;
    }
    if (!m.popping_raster)
        m.popping_raster = std::make_unique<PoppingRaster>(f);
    return m.withCaptureFrame(
        camera, s, nullptr, true, [&](TerrainScheme& scheme, const SchemeFrame& frame) {
            const size_t n = m.recordInstances(scheme, frame);
            return m.popping_raster->next(m.surface_capture.feedback(), n, camera);
        });
}

void TerrainRenderer::resetPopping()
{
    Impl& m = *impl_;
    m.popping_previous.reset();
    if (m.popping_raster)
        m.popping_raster->reset();
}

double TerrainRenderer::groundHeight(double x, double y, double exaggeration) const
{
    checkParameter("exaggeration", exaggeration, RenderSettings::kExaggerationRange);
    return exaggeration * impl_->coarse.groundHeight(x, y);
}

double TerrainRenderer::groundUnder(glm::dvec3 world, double exaggeration) const
{
    checkParameter("exaggeration", exaggeration, RenderSettings::kExaggerationRange);
    return exaggeration * impl_->coarse.groundUnder(world);
}

lod::Camera TerrainRenderer::cameraLookingAt(glm::dvec3 position, glm::dvec3 look_at,
                                             double fov_y_degrees, lod::Viewport viewport,
                                             double exaggeration) const
{
    checkParameters("camera position", &position.x, 3, lod::kCameraCoordinateRange);
    double near_m = 1.0, far_m = 1e6;
    clipPlanesFor(position, near_m, far_m, exaggeration);
    return lod::Camera(position, look_at, fov_y_degrees, viewport, near_m, far_m,
                       impl_->quadtree.frame().upThrough(position));
}

void TerrainRenderer::clipPlanesFor(glm::dvec3 position, double& near_m, double& far_m,
                                    double exaggeration) const
{
    if (exaggeration == 1.0)
        return impl_->coarse.clipPlanesFor(position, near_m, far_m);
    impl_->coarse.exaggerated(exaggeration).clipPlanesFor(position, near_m, far_m);
}

lod::Camera TerrainRenderer::defaultCamera(lod::Viewport viewport, double fov_y_degrees,
                                           double exaggeration) const
{
    if (exaggeration == 1.0)
        return impl_->coarse.defaultCamera(viewport, fov_y_degrees);
    return impl_->coarse.exaggerated(exaggeration).defaultCamera(viewport, fov_y_degrees);
}

} // namespace ridge::render
