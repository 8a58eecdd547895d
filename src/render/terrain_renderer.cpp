#include "ridge/render/terrain_renderer.h"

#include "palette_uniforms.h"
#include "patch_instances.h"
#include "patch_textures.h"
#include "terrain_scheme.h"

#include "ridge/core/error.h"
#include "ridge/gpu/gl_objects.h"
#include "ridge/gpu/gpu_timer.h"
#include "ridge/gpu/render_target.h"
#include "ridge/gpu/shader_program.h"
#include "ridge/lod/coarse_terrain.h"
#include "ridge/lod/edge_tessellation.h"
#include "ridge/lod/resident_cover.h"
#include "ridge/lod/screen_space_error.h"
#include "ridge/stream/patch_loader.h"
#include "ridge/stream/patch_streamer.h"
#include "ridge/stream/upload_planner.h"

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
#include <unordered_set>

namespace ridge::render {
namespace {

static_assert(sizeof(CapturedVertex) == 20, "must match the interleaved feedback varyings");

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

namespace {

// Whether patches may carry water bitmaps (archive sample flags with any water sample): only
// then does each slot hold an n² water map.
bool hasWaterMaps(const archive::ArchiveReader& reader)
{
    return reader.storesSampleFlags() && reader.metadata().water.samples > 0;
}

// Slots for resident patches: the requested count within the VRAM budget and the GL limit on
// array layers; at least 4, so that raising ε always finds a selection that fits.
int slotCount(const archive::ArchiveReader& reader, const RendererOptions& options,
              double scheme_slot_bytes)
{
    const double n = reader.geometry().patchSize();
    const double blocks = double(reader.blockLayout().blocksPerSide());
    // Heights R16UI and normals RGBA8 (n²), block errors RGBA32F, the kept-nodata cell mask
    // R8UI ((n−1)², allocated for every slot) and its flag, the water map R8UI (n², only for
    // archives with water), and what the scheme adds.
    const double bytes_per_slot = n * n * (2.0 + 4.0 + (hasWaterMaps(reader) ? 1.0 : 0.0)) +
                                  blocks * blocks * 16.0 + (n - 1) * (n - 1) + 1.0 +
                                  scheme_slot_bytes;
    GLint max_layers = 256;
    glGetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &max_layers);
    const double by_budget = std::floor(options.vram_budget_mb * 1024.0 * 1024.0 / bytes_per_slot);
    const int wanted =
        int(std::min({double(options.max_resident_patches), by_budget, double(max_layers)}));
    const int minimum = 4;
    if (wanted < minimum) {
        char message[160];
        std::snprintf(
            message, sizeof message,
            ": patches of %d^2 samples need %.3g MB of texture memory at least; the budget "
            "is %.3g MB",
            int(n), minimum * bytes_per_slot / 1048576.0, options.vram_budget_mb);
        throw Error(reader.path() + message);
    }
    return wanted;
}

// The schemes `options` asks for (all registered ones that need no CPU codes with their
// default options when empty), with their own options and what each needs.
struct PlannedSchemes {
    std::vector<const SchemeInfo*> infos;
    std::vector<SchemeOptions> own; // per scheme: its options, from its spec
    std::vector<SchemeNeeds> needs;
    double slot_bytes = 0.0;
    bool codes_on_cpu = false;
    std::vector<stream::PatchPreparation> preparations;
    std::vector<int> product; // per scheme: index into preparations, or −1
};

PlannedSchemes planSchemes(const archive::ArchiveReader& reader, const RendererOptions& options)
{
    PlannedSchemes out;
    auto add = [&](const SchemeInfo& info, SchemeOptions own, SchemeNeeds needs) {
        out.infos.push_back(&info);
        out.own.push_back(std::move(own));
        out.slot_bytes += needs.slot_bytes;
        out.codes_on_cpu = out.codes_on_cpu || needs.codes_on_cpu;
        out.product.push_back(needs.preparation ? int(out.preparations.size()) : -1);
        if (needs.preparation)
            out.preparations.push_back(needs.preparation);
        out.needs.push_back(std::move(needs));
    };
    if (options.schemes.empty()) {
        for (const SchemeInfo& info : schemeRegistry()) {
            SchemeOptions own = parseSchemeSpec(info.name);
            if (SchemeNeeds needs = info.needs(reader, options, own); !needs.codes_on_cpu)
                add(info, std::move(own), std::move(needs));
        }
    } else {
        for (const std::string& spec : options.schemes) { // validate(): one spec per scheme
            SchemeOptions own = parseSchemeSpec(spec);
            const SchemeInfo& info = schemeNamed(own.scheme());
            SchemeNeeds needs = info.needs(reader, options, own);
            add(info, std::move(own), std::move(needs));
        }
    }
    return out;
}

} // namespace

struct TerrainRenderer::Impl {
    const archive::ArchiveReader& reader;
    RendererOptions options;
    PlannedSchemes planned;
    lod::PatchQuadtree quadtree;
    int slots = 0; // texture-array layers
    lod::PatchResidency residency;
    stream::PatchLoader loader;
    TessellationBlockLayout layout;
    HeightQuantization quantization;
    int n = 0;                                // samples per patch side
    int blocks_per_side = 0;                  // B
    int block_levels = 0;                     // D
    float min_height = 0.f, max_height = 0.f; // terrain frame, metres
    double skirt_margin = 0.0;                // float rounding of camera-relative heights
    // The level-0 patch on the CPU: ground heights and clip planes for cameras.
    std::optional<lod::CoarseTerrain> coarse;
    uint64_t frame = 0;

    std::unique_ptr<PatchTextures> textures;
    // Streaming mode: decoded patches arrive from the streamer's workers and wait here for an
    // upload slot in a later frame.
    std::unique_ptr<stream::PatchStreamer> streamer;
    std::vector<std::shared_ptr<const stream::DecodedPatch>> arrived, waiting;
    std::vector<stream::ArrivedPatch> arrived_descriptions; // capacity kept across frames
    std::unique_ptr<stream::UploadPlanner> planner;
    // The upload time budget follows the frame time, measured on this clock (ms since epoch).
    stream::UploadTimeBudget upload_time{{options.upload_budget_ms, options.upload_frame_fraction,
                                          options.upload_budget_max_ms}};
    const std::chrono::steady_clock::time_point epoch = std::chrono::steady_clock::now();
    // Traffic counters at the end of the previous frame (FrameStats reports the difference).
    stream::StreamerStats last_streamer_stats;
    stream::LoaderStats last_loader_stats;
    std::vector<PatchId> last_drawn;
    // What the last draw() drew, for lastFrameSurface() (picking): replayed, not re-selected.
    struct LastFrame {
        lod::Camera camera, lod_camera;
        RenderSettings settings; // with the ε met
        PatchInstances instances;
        TerrainScheme* scheme = nullptr;
    };
    std::optional<LastFrame> last_frame;
    gpu::GlBuffer instances;
    size_t instance_capacity = 0;
    gpu::GlBuffer feedback;
    size_t feedback_capacity = 0; // bytes
    gpu::GlVertexArray empty_vao;
    // The drawable schemes (planned.infos order), each over the shared pieces above.
    std::vector<std::unique_ptr<TerrainScheme>> schemes;
    std::vector<std::string> scheme_names;
    gpu::ShaderProgram sky_program;
    gpu::GpuTimer timer;                              // terrain pass
    gpu::GpuTimer upload_timer;                       // uploads and normal maps of new patches
    gpu::GlQuery primitives{GL_PRIMITIVES_GENERATED}; // capture(), synchronous stats
    // Triangles of the terrain pass for interactive use: a ring of queries read only once
    // their results are available, so counting never stalls the pipeline.
    static constexpr int kTriangleQueries = 4;
    std::vector<gpu::GlQuery> triangle_queries;
    std::vector<bool> triangle_query_pending = std::vector<bool>(kTriangleQueries, false);
    int next_triangle_query = 0;
    uint64_t last_triangles = 0;
    uint64_t latestTriangles();
    gpu::GlQuery written{GL_TRANSFORM_FEEDBACK_PRIMITIVES_WRITTEN};
    // Drawing needs a complete framebuffer even with the rasterizer discarded; a surfaceless
    // context has none, so capture binds this one.
    std::unique_ptr<gpu::RenderTarget> capture_target;

    Impl(const archive::ArchiveReader& r, const RendererOptions& o);
    void makeResident(const lod::Selection& selection, FrameStats& stats);
    // Streaming: requests what is missing, uploads what arrived (within the per-frame budget)
    // and returns what to draw now — missing patches replaced by resident ancestors.
    lod::Selection streamResident(const lod::Selection& desired, FrameStats& stats,
                                  const lod::Camera& camera,
                                  const lod::SelectionSettings& settings);
    size_t uploadPatch(const stream::DecodedPatch& patch, int slot,
                       const std::unordered_set<int>& pending_slots = {});
    // What uploading `patch` will send, at most (the per-frame budget plans with it).
    size_t plannedUploadBytes(const stream::DecodedPatch& patch) const
    {
        size_t bytes = textures->uploadBytes(patch);
        for (const auto& scheme : schemes)
            bytes += scheme->plannedUploadBytes(patch);
        return bytes;
    }
    // The scheme `settings` names; throws when this renderer was not built for it.
    TerrainScheme& schemeFor(const RenderSettings& settings) const;
    void countTraffic(FrameStats& stats);
    void computeNormals(PatchId p, const std::unordered_set<int>& pending);
    PatchInstances writeInstances(const lod::Camera& camera, const lod::Camera& lod_camera,
                                  const lod::Selection& selection, const RenderSettings& settings);
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
        return writeInstances(camera, lod_camera, selection, used);
    }
    void setFrameUniforms(const gpu::ShaderProgram& program, const SchemeFrame& frame) const;
    // Calls draw(program, first, count) for the non-empty instance groups: whole patches with
    // the scheme's plain (or capture) program, partial ones with its clipping one.
    template <class Draw>
    void forEachGroup(TerrainScheme& scheme, const PatchInstances& r, Draw&& draw,
                      bool capture) const
    {
        const auto [whole, clip] = scheme.programs(capture);
        if (r.whole)
            draw(*whole, size_t(0), r.whole);
        if (r.partial)
            draw(*clip, r.whole, r.partial);
    }
    // Captures the triangles of `ranges` (already in the instance buffer) drawn as `frame`.
    CapturedSurface captureInstances(TerrainScheme& scheme, const SchemeFrame& frame,
                                     const PatchInstances& ranges);
    // `frozen`: draw what is resident (resident cover), changing nothing.
    lod::Selection prepare(const lod::Camera& camera, const RenderSettings& settings,
                           FrameStats& stats, bool frozen = false);
};

TerrainRenderer::Impl::Impl(const archive::ArchiveReader& r, const RendererOptions& o)
    : reader(r), options(o), planned(planSchemes(r, o)), quadtree(lod::PatchQuadtree::fromArchive(r)),
      slots(slotCount(r, o, planned.slot_bytes)), residency(r.geometry(), slots),
      loader(r, o.decoded_cache_patches, planned.preparations), layout(r.blockLayout()),
      quantization(r.quantization())
{
    n = reader.geometry().patchSize();
    blocks_per_side = layout.blocksPerSide();
    block_levels = std::min(layout.levels(), lod::kMaxBlockLevels);
    const lod::PatchBounds& root = quadtree.bounds(PatchId{0, 0, 0});
    min_height = root.min_height;
    max_height = root.max_height;
    // Float rounding of camera-relative heights: a centimetre plus a few ulps of the highest.
    skirt_margin = 0.01 + 1e-6 * std::max(std::abs(root.min_height), std::abs(root.max_height));
    coarse.emplace(quadtree.frame(), quadtree.box(PatchId{0, 0, 0}),
                   loader.load(PatchId{0, 0, 0})->codes, quantization);

    // The codec's GPU reconstruction, unless a drawable scheme needs codes on the CPU.
    const ProgressiveCodec* gpu_codec =
        options.streaming && options.gpu_reconstruction && !planned.codes_on_cpu
            ? reader.codec().capabilities().gpu_reconstruction
            : nullptr;
    textures = std::make_unique<PatchTextures>(n, layout, block_levels, slots, quantization,
                                               gpu_codec, hasWaterMaps(reader));
    for (size_t k = 0; k < planned.infos.size(); ++k)
        schemes.push_back(planned.infos[k]->make(
            SchemeResources{reader, quadtree, options, planned.own[k], *textures, residency, slots,
                            planned.product[k]}));
    for (const SchemeInfo* info : planned.infos)
        scheme_names.push_back(info->name);
    if (options.streaming) {
        stream::StreamerOptions so = stream::StreamerOptions::forRamBudget(
            size_t(options.ram_budget_mb * 1024.0 * 1024.0), options.io_threads);
        so.residuals_for_gpu = gpu_codec != nullptr;
        so.preparations = planned.preparations;
        streamer = std::make_unique<stream::PatchStreamer>(reader, so);
        // The root stays resident: the last resort of every fallback.
        const PatchId root{0, 0, 0};
        for (const lod::PatchResidency::Load& l : residency.update({root}, ++frame))
            uploadPatch(*loader.load(l.id), l.slot);
        computeNormals(root, {});
        textures->finishUploads();
        planner = std::make_unique<stream::UploadPlanner>(reader.geometry(), residency);
    }
    sky_program =
        gpu::ShaderProgram({{GL_VERTEX_SHADER, "sky.vert"}, {GL_FRAGMENT_SHADER, "sky.frag"}});
}

TerrainScheme& TerrainRenderer::Impl::schemeFor(const RenderSettings& settings) const
{
    for (size_t k = 0; k < planned.infos.size(); ++k)
        if (settings.scheme == planned.infos[k]->name)
            return *schemes[k];
    std::string built;
    for (const SchemeInfo* info : planned.infos)
        built += (built.empty() ? "" : ", ") + std::string(info->name);
    throw Error(reader.path() + ": LOD scheme '" + settings.scheme +
                "' is not one this renderer was built for (RendererOptions::schemes: " + built +
                ")");
}

// Makes `patch` resident in `slot`: codes are uploaded, residuals reconstructed on the GPU
// from the parent's slot. Slots in `pending_slots` are assigned this frame but not yet
// written: their content must not be read. Returns the bytes sent. The normal map follows in
// computeNormals.
size_t TerrainRenderer::Impl::uploadPatch(const stream::DecodedPatch& patch, int slot,
                                          const std::unordered_set<int>& pending_slots)
{
    const PatchId p = patch.id;
    const lod::PatchBounds& bounds = quadtree.bounds(p);
    const float lambda_cap = bounds.max_height - bounds.min_height;
    if (!patch.needsGpuReconstruction()) {
        textures->upload(patch, slot, lambda_cap);
        size_t bytes = textures->uploadBytes(patch);
        for (const auto& scheme : schemes)
            bytes += scheme->upload(patch, slot);
        return bytes;
    }
    const int parent_slot = residency.slotOf(p.parent());
    if (parent_slot < 0 || pending_slots.count(parent_slot))
        throw Error(reader.describe(p) + ": internal: parent not resident for GPU reconstruction");
    textures->reconstruct(patch, parent_slot, slot, lambda_cap);
    return textures->uploadBytes(patch);
}

// The normal map of `p`, just made resident, and those of its resident same-level
// neighbours, whose borders now have a real neighbour instead of an extrapolated one: every
// same-level seam between resident patches gets the same normals on both sides, whatever
// order the patches arrived in. Slots in `pending` (assigned, not yet written) are treated as
// absent; when one is written it refreshes its neighbours in turn.
void TerrainRenderer::Impl::computeNormals(PatchId p, const std::unordered_set<int>& pending)
{
    const PyramidGeometry& g = reader.geometry();
    auto sidesOf = [](PatchId q) {
        return std::array<PatchId, 4>{
            PatchId{q.level, q.x - 1, q.y}, PatchId{q.level, q.x + 1, q.y},
            PatchId{q.level, q.x, q.y - 1}, PatchId{q.level, q.x, q.y + 1}};
    };
    auto writtenSlot = [&](PatchId q) {
        const int s = g.exists(q) ? residency.slotOf(q) : -1;
        return s >= 0 && !pending.count(s) ? s : -1;
    };
    auto normalsOf = [&](PatchId q) {
        std::array<int, 4> neighbours{-1, -1, -1, -1};
        if (options.seamless_normals) {
            const std::array<PatchId, 4> sides = sidesOf(q);
            for (size_t k = 0; k < 4; ++k)
                neighbours[k] = writtenSlot(sides[k]);
        }
        const double step = double(g.step(q.level));
        textures->computeNormals(residency.slotOf(q), neighbours, step * reader.header().spacing_x,
                                 step * reader.header().spacing_y);
    };
    normalsOf(p);
    if (options.seamless_normals)
        for (PatchId q : sidesOf(p))
            if (writtenSlot(q) >= 0)
                normalsOf(q);
}

void TerrainRenderer::Impl::makeResident(const lod::Selection& selection, FrameStats& stats)
{
    std::vector<PatchId> ids;
    ids.reserve(selection.patches.size());
    for (const lod::SelectedPatch& s : selection.patches)
        ids.push_back(s.id);
    const auto loads = residency.update(ids, ++frame);
    std::unordered_set<int> pending;
    for (const lod::PatchResidency::Load& l : loads)
        pending.insert(l.slot);
    for (size_t k = 0; k < loads.size(); ++k) {
        try {
            stats.bytes_uploaded += uploadPatch(*loader.load(loads[k].id), loads[k].slot);
        } catch (...) {
            // The failed patch and those after it were given slots they never filled.
            for (size_t j = k; j < loads.size(); ++j)
                residency.release(loads[j].id);
            textures->finishUploads();
            throw;
        }
        pending.erase(loads[k].slot);
        computeNormals(loads[k].id, pending);
    }
    if (!loads.empty())
        textures->finishUploads();
    stats.loaded = int(loads.size());
    stats.resident = residency.residentCount();
}

PatchInstances TerrainRenderer::Impl::writeInstances(const lod::Camera& camera,
                                                     const lod::Camera& lod_camera,
                                                     const lod::Selection& selection,
                                                     const RenderSettings& settings)
{
    // Skirts hang by what the scheme's mesh drops beyond Err(P) (the tessellator's λ, a
    // chunk's simplification error, ...).
    const TerrainScheme& scheme = schemeFor(settings);
    // Camera-relative heights are floats: a skirt must also hang a few ulps of the largest
    // |z − camera z| (2^−22 ≈ 2.4e−7 of it, times 4), or over flat ground (Err and λ 0), seen
    // from far above, its foot rounds onto its top and the seam it closes opens (found when
    // the texture-detail criterion split flat sea into levels seen from 760 km).
    const double k = settings.exaggeration;
    const double z_rel = std::max(std::abs(camera.position().z - k * double(min_height)),
                                  std::abs(camera.position().z - k * double(max_height)));
    PatchInstances built = buildPatchInstances(
        quadtree, selection, camera.position(), [&](PatchId p) { return residency.slotOf(p); },
        [&](PatchId p) { return scheme.meshDeviation(residency.slotOf(p)); },
        skirt_margin * std::max(k, 1.0) + 1e-6 * z_rel, k);
    scheme.completeInstances(lod_camera, settings, built);
    const std::vector<GpuPatchInstance>& data = built.records;
    const size_t bytes = std::max<size_t>(data.size(), 1) * sizeof(GpuPatchInstance);
    if (bytes > instance_capacity) {
        instances = gpu::GlBuffer();
        instance_capacity = std::max(bytes, size_t(256) * sizeof(GpuPatchInstance));
        glNamedBufferStorage(instances.id(), instance_capacity, nullptr, GL_DYNAMIC_STORAGE_BIT);
    }
    if (!data.empty())
        glNamedBufferSubData(instances.id(), 0, data.size() * sizeof(GpuPatchInstance),
                             data.data());
    return built;
}

void TerrainRenderer::Impl::setFrameUniforms(const gpu::ShaderProgram& program,
                                             const SchemeFrame& frame) const
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
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, instances.id());
    textures->bind();
    schemeFor(settings).setUniforms(program, frame);
}

lod::Selection TerrainRenderer::Impl::prepare(const lod::Camera& camera,
                                              const RenderSettings& settings, FrameStats& stats,
                                              bool frozen)
{
    textures->collect(); // λ maxima derived on the GPU in earlier frames
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
    if (frozen) {
        // What is resident now, ancestors standing in for the rest: no request, no upload.
        selection.patches = lod::residentCover(selection, reader.geometry(), [&](PatchId p) {
                                return residency.slotOf(p) >= 0;
                            }).patches;
        return selection;
    }
    upload_timer.begin();
    try {
        if (streamer)
            selection = streamResident(selection, stats, camera, ss);
        else
            makeResident(selection, stats);
    } catch (...) {
        upload_timer.end(); // keep begin/end balanced for the next frame
        throw;
    }
    upload_timer.end();
    stats.gpu_upload_ms = options.synchronous_stats ? upload_timer.waitMs() : upload_timer.lastMs();
    stats.cpu_load_ms = millisecondsSince(t0);
    countTraffic(stats);
    stats.patches = int(selection.patches.size());
    last_drawn.clear();
    for (const lod::SelectedPatch& p : selection.patches)
        last_drawn.push_back(p.id);
    return selection;
}

// Streaming, executed: the GL-free stream::UploadPlanner decides what to request, what stays
// resident, what to upload this frame and into which slot; this uploads it (stopping when the
// time budget is spent) and tells the planner how far it got.
lod::Selection TerrainRenderer::Impl::streamResident(const lod::Selection& desired,
                                                     FrameStats& stats, const lod::Camera& camera,
                                                     const lod::SelectionSettings& settings)
{
    // Each streamed frame's time budget follows the frame time (stream::UploadTimeBudget).
    stats.upload_budget_ms = upload_time.beginFrame(millisecondsSince(epoch));
    streamer->beginFrame();
    for (auto& patch : streamer->takeReady())
        arrived.push_back(std::move(patch));
    arrived_descriptions.clear();
    for (size_t k = 0; k < arrived.size(); ++k)
        arrived_descriptions.push_back({arrived[k]->id, plannedUploadBytes(*arrived[k]),
                                        arrived[k]->needsGpuReconstruction(), k});
    const stream::StreamPlan& plan =
        planner->plan(desired, arrived_descriptions,
                      {size_t(options.upload_budget_mb * 1024.0 * 1024.0), options.uploads_per_frame});
    planner->prefetch(quadtree, camera, options.prefetch_frames, settings);
    for (const stream::StreamRequest& r : plan.requests)
        streamer->request(r.id, r.priority);

    std::unordered_set<int> pending_slots;
    for (const stream::PlannedUpload& u : plan.uploads)
        pending_slots.insert(u.slot);
    // Coarse first (the plan's order), so that a parent uploaded this frame is written before
    // its children.
    const auto t0 = std::chrono::steady_clock::now();
    size_t done = 0;
    try {
        for (; done < plan.uploads.size(); ++done) {
            if (!upload_time.mayStart(done, millisecondsSince(t0)))
                break; // the time budget: the rest waits for the next frame
            const stream::PlannedUpload& u = plan.uploads[done];
            stats.bytes_uploaded += uploadPatch(*arrived[u.handle], u.slot, pending_slots);
            pending_slots.erase(u.slot);
            computeNormals(u.id, pending_slots); // inside the time budget too
        }
    } catch (...) {
        planner->finish(done); // the failed upload and those after it give their slots back
        throw;
    }
    upload_time.endFrame(done > 0 ? millisecondsSince(t0) : 0.0);
    const stream::StreamOutcome& outcome = planner->finish(done);
    waiting.clear();
    for (size_t h : outcome.waiting)
        waiting.push_back(std::move(arrived[h]));
    arrived.swap(waiting);
    if (done > 0)
        textures->finishUploads();
    stats.loaded = outcome.uploaded;
    stats.reconstructed = outcome.reconstructed;
    stats.missing = outcome.missing;
    stats.resident = residency.residentCount();
    return outcome.drawn;
}

void TerrainRenderer::Impl::countTraffic(FrameStats& stats)
{
    if (streamer) {
        const stream::StreamerStats now = streamer->stats();
        stats.bytes_read = now.bytes_read - last_streamer_stats.bytes_read;
        stats.bytes_decoded = now.bytes_decoded - last_streamer_stats.bytes_decoded;
        stats.cache_hits = int(now.cache_hits - last_streamer_stats.cache_hits);
        stats.cache_misses = int(now.requested - last_streamer_stats.requested);
        last_streamer_stats = now;
    } else {
        const stream::LoaderStats& now = loader.stats();
        stats.bytes_read = now.bytes_read - last_loader_stats.bytes_read;
        stats.cache_hits = int(now.cache_hits - last_loader_stats.cache_hits);
        stats.cache_misses = int(now.decoded - last_loader_stats.decoded);
        stats.bytes_decoded = now.bytes_decoded - last_loader_stats.bytes_decoded;
        last_loader_stats = now;
    }
}

uint64_t TerrainRenderer::Impl::latestTriangles()
{
    // Oldest first, so the newest available result wins.
    for (int k = 1; k <= kTriangleQueries; ++k) {
        const int q = (next_triangle_query + k) % kTriangleQueries;
        if (!triangle_query_pending[size_t(q)])
            continue;
        GLuint available = 0;
        glGetQueryObjectuiv(triangle_queries[size_t(q)].id(), GL_QUERY_RESULT_AVAILABLE,
                            &available);
        if (!available)
            continue;
        GLuint64 generated = 0;
        glGetQueryObjectui64v(triangle_queries[size_t(q)].id(), GL_QUERY_RESULT, &generated);
        last_triangles = generated;
        triangle_query_pending[size_t(q)] = false;
    }
    return last_triangles;
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
    return impl_->scheme_names;
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
    if (impl_->streamer)
        impl_->streamer->waitIdle();
}

bool TerrainRenderer::waitForStreaming(double timeout_seconds)
{
    // A billion seconds (32 years) keeps the deadline within the clock's range.
    checkParameter("streaming wait timeout (s)", timeout_seconds, ValueRange::closed(0.0, 1e9));
    return !impl_->streamer || impl_->streamer->waitIdleFor(timeout_seconds);
}

std::string TerrainRenderer::streamingError() const
{
    return impl_->streamer ? impl_->streamer->error() : std::string();
}

uint64_t TerrainRenderer::cacheMisses() const
{
    return impl_->streamer ? impl_->streamer->stats().requested : impl_->loader.stats().decoded;
}

uint64_t TerrainRenderer::cacheHits() const
{
    return impl_->streamer ? impl_->streamer->stats().cache_hits : impl_->loader.stats().cache_hits;
}

std::vector<uint16_t> TerrainRenderer::residentCodes(PatchId p) const
{
    const int slot = impl_->residency.slotOf(p);
    if (slot < 0)
        return {};
    const int n = impl_->n;
    std::vector<uint16_t> codes(size_t(n) * n);
    glPixelStorei(GL_PACK_ALIGNMENT, 2);
    glGetTextureSubImage(impl_->textures->heights(), 0, 0, 0, slot, n, n, 1, GL_RED_INTEGER,
                         GL_UNSIGNED_SHORT, GLsizei(codes.size() * sizeof(uint16_t)), codes.data());
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    gpu::checkGlError("terrain renderer: read resident codes");
    return codes;
}

std::vector<float> TerrainRenderer::residentBlockErrors(PatchId p) const
{
    const int slot = impl_->residency.slotOf(p);
    if (slot < 0)
        return {};
    const int B = impl_->blocks_per_side, D = impl_->layout.levels();
    std::vector<float> texels(size_t(B) * B * 4);
    glGetTextureSubImage(impl_->textures->blockErrors(), 0, 0, 0, slot, B, B, 1, GL_RGBA, GL_FLOAT,
                         GLsizei(texels.size() * sizeof(float)), texels.data());
    gpu::checkGlError("terrain renderer: read resident block errors");
    std::vector<float> lambda(size_t(B) * B * D, 0.f);
    for (int b = 0; b < B * B; ++b)
        for (int d = 0; d < std::min(D, 4); ++d)
            lambda[size_t(b) * D + d] = texels[size_t(b) * 4 + d];
    return lambda;
}

std::vector<int8_t> TerrainRenderer::residentNormals(PatchId p) const
{
    const int slot = impl_->residency.slotOf(p);
    if (slot < 0)
        return {};
    const int n = impl_->n;
    std::vector<int8_t> texels(size_t(n) * n * 4);
    glGetTextureSubImage(impl_->textures->normals(), 0, 0, 0, slot, n, n, 1, GL_RGBA, GL_BYTE,
                         GLsizei(texels.size()), texels.data());
    gpu::checkGlError("terrain renderer: read resident normals");
    return texels;
}

double TerrainRenderer::residentLambdaMax(PatchId p) const
{
    const int slot = impl_->residency.slotOf(p);
    return slot < 0 ? -1.0 : double(impl_->textures->lambdaMax(slot));
}

size_t TerrainRenderer::streamingCacheBytes() const
{
    if (!impl_->streamer)
        return 0;
    const stream::StreamerStats s = impl_->streamer->stats();
    return s.cache_bytes + s.compressed_bytes;
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
        m.forEachGroup(
            scheme, ranges,
            [&](const gpu::ShaderProgram& p, size_t first, size_t n) {
                p.use();
                glUniform1i(p.uniform("u_mode"), mode);
                scheme.draw(p, frame, first, n);
            },
            false);
    };

    const bool synchronous = m.options.synchronous_stats;
    if (m.triangle_queries.empty())
        for (int k = 0; k < Impl::kTriangleQueries; ++k)
            m.triangle_queries.emplace_back(GL_PRIMITIVES_GENERATED);
    const int query = m.next_triangle_query;
    m.next_triangle_query = (query + 1) % Impl::kTriangleQueries;
    m.timer.begin();
    // A still-pending query in this slot is dropped: its frame is 4 frames old.
    glBeginQuery(GL_PRIMITIVES_GENERATED, m.triangle_queries[size_t(query)].id());
    drawTerrain(int(s.mode));
    glEndQuery(GL_PRIMITIVES_GENERATED);
    m.triangle_query_pending[size_t(query)] = true;
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
    if (synchronous) {
        GLuint64 generated = 0;
        glGetQueryObjectui64v(m.triangle_queries[size_t(query)].id(), GL_QUERY_RESULT, &generated);
        m.triangle_query_pending[size_t(query)] = false;
        m.last_triangles = generated;
        stats.triangles = generated;
    } else {
        stats.triangles = m.latestTriangles();
    }
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
    return m.captureInstances(*f.scheme, frame, f.instances);
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
    return m.captureInstances(scheme, frame, ranges);
}

CapturedSurface TerrainRenderer::Impl::captureInstances(TerrainScheme& scheme,
                                                        const SchemeFrame& frame,
                                                        const PatchInstances& ranges)
{
    Impl& m = *this;
    const RenderSettings& s = frame.settings;
    CapturedSurface out;
    out.camera_position = frame.camera.position();
    out.patches = ranges.patches;
    for (const GpuPatchInstance& r : ranges.records)
        out.skirt_depth.push_back(r.skirt_depth);
    if (ranges.total() == 0)
        return out;

    scheme.beginDraw(frame);
    for (const gpu::ShaderProgram* p : scheme.programs(true))
        m.setFrameUniforms(*p, frame);
    GLint previous_framebuffer = 0;
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &previous_framebuffer);
    if (!m.capture_target)
        m.capture_target = std::make_unique<gpu::RenderTarget>(1, 1, 1);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, m.capture_target->framebuffer());
    glEnable(GL_RASTERIZER_DISCARD);
    // Clipping makes at most 3 triangles and 2 walls (4 triangles) of one.
    const size_t per_instance = scheme.maxTrianglesPerInstance(s.skirts);
    const size_t bytes =
        (ranges.whole + 7 * ranges.partial) * per_instance * 3 * sizeof(CapturedVertex);
    if (bytes > m.feedback_capacity) {
        m.feedback = gpu::GlBuffer();
        glNamedBufferStorage(m.feedback.id(), bytes, nullptr, 0);
        m.feedback_capacity = bytes;
    }
    // One feedback session per program (programs cannot change while it is active); the
    // second appends after the first.
    size_t stored_total = 0;
    m.forEachGroup(
        scheme, ranges,
        [&](const gpu::ShaderProgram& p, size_t first, size_t n) {
            p.use();
            const GLintptr offset = GLintptr(stored_total * 3 * sizeof(CapturedVertex));
            glBindBufferRange(GL_TRANSFORM_FEEDBACK_BUFFER, 0, m.feedback.id(), offset,
                              GLsizeiptr(m.feedback_capacity - size_t(offset)));
            glBeginQuery(GL_TRANSFORM_FEEDBACK_PRIMITIVES_WRITTEN, m.written.id());
            glBeginQuery(GL_PRIMITIVES_GENERATED, m.primitives.id());
            glBeginTransformFeedback(GL_TRIANGLES);
            scheme.draw(p, frame, first, n);
            glEndTransformFeedback();
            glEndQuery(GL_PRIMITIVES_GENERATED);
            glEndQuery(GL_TRANSFORM_FEEDBACK_PRIMITIVES_WRITTEN);
            GLuint64 generated = 0, stored = 0;
            glGetQueryObjectui64v(m.primitives.id(), GL_QUERY_RESULT, &generated);
            glGetQueryObjectui64v(m.written.id(), GL_QUERY_RESULT, &stored);
            if (generated != stored)
                throw Error("terrain renderer: transform feedback kept " + std::to_string(stored) +
                            " of " + std::to_string(generated) + " triangles");
            stored_total += size_t(stored);
        },
        true);
    glDisable(GL_RASTERIZER_DISCARD);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, GLuint(previous_framebuffer));
    const size_t stored = stored_total;
    out.vertices.resize(size_t(stored) * 3);
    glGetNamedBufferSubData(m.feedback.id(), 0, out.vertices.size() * sizeof(CapturedVertex),
                            out.vertices.data());
    gpu::checkGlError("terrain renderer: capture");
    return out;
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
