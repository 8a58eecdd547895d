#include "ridge/render/terrain_renderer.h"

#include "patch_instances.h"
#include "patch_textures.h"

#include "ridge/core/error.h"
#include "ridge/gpu/gl_objects.h"
#include "ridge/gpu/gpu_timer.h"
#include "ridge/gpu/render_target.h"
#include "ridge/gpu/shader_program.h"
#include "ridge/lod/chunk_mesh.h"
#include "ridge/lod/coarse_terrain.h"
#include "ridge/lod/edge_tessellation.h"
#include "ridge/lod/resident_cover.h"
#include "ridge/lod/screen_space_error.h"
#include "ridge/stream/patch_loader.h"
#include "ridge/stream/patch_streamer.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_inverse.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>
#include <unordered_map>
#include <unordered_set>

namespace ridge::render {
namespace {

static_assert(sizeof(CapturedVertex) == 20, "must match the interleaved feedback varyings");

double millisecondsSince(std::chrono::steady_clock::time_point t0)
{
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// Reverse-Z infinite perspective (depth 1 at the near plane, 0 at infinity) for
// glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE). Its x, y and w rows equal those of
// Camera::projection(), so screen-space measurements in the shaders match the C++ ones.
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

void setMatrix(const gpu::ShaderProgram& program, const char* name, const glm::dmat4& m)
{
    const glm::mat4 f(m);
    glProgramUniformMatrix4fv(program.id(), program.uniform(name), 1, GL_FALSE, glm::value_ptr(f));
}

} // namespace

namespace {

// Ulrich's chunks: vertex ids run to n² + 4(n − 1) (the skirt's feet); 16-bit while they fit.
GLenum chunkIndexType(int n)
{
    return int64_t(n) * n + 4 * int64_t(n - 1) <= 65536 ? GL_UNSIGNED_SHORT : GL_UNSIGNED_INT;
}

// The index buffer of an unsimplified chunk: two triangles per cell, two per border cell of
// the skirt.
size_t worstChunkMeshBytes(int n)
{
    const size_t c = size_t(n - 1);
    return (6 * c * c + 24 * c) * (chunkIndexType(n) == GL_UNSIGNED_SHORT ? 2 : 4);
}

// Slots for resident patches: the requested count within the VRAM budget and the GL limit on
// array layers; at least 4, so that raising ε always finds a selection that fits.
int slotCount(const archive::ArchiveReader& reader, const RendererOptions& options)
{
    const double n = reader.geometry().patchSize();
    const double blocks = double(reader.blockLayout().blocksPerSide());
    const double bytes_per_slot =
        n * n * (2.0 + 4.0) + blocks * blocks * 16.0 + // R16UI, RGBA8, RGBA32F
        (options.chunk_meshes ? double(worstChunkMeshBytes(int(n))) : 0.0);
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

} // namespace

struct TerrainRenderer::Impl {
    const archive::ArchiveReader& reader;
    RendererOptions options;
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
    std::vector<std::shared_ptr<const stream::DecodedPatch>> arrived;
    // Traffic counters at the end of the previous frame (FrameStats reports the difference).
    stream::StreamerStats last_streamer_stats;
    stream::LoaderStats last_loader_stats;
    std::vector<PatchId> last_drawn;
    // Camera-path extrapolation for prefetching (the JPEG 2000 terrain paper, §4).
    bool has_last_camera = false;
    glm::dvec3 last_camera{0.0};
    gpu::GlBuffer instances;
    size_t instance_capacity = 0;
    gpu::GlBuffer feedback;
    size_t feedback_capacity = 0; // bytes
    gpu::GlVertexArray empty_vao;
    // Chunked LOD and brute force: one index buffer for every patch (see shaders/chunk.vert).
    gpu::GlVertexArray chunk_vao;
    gpu::GlBuffer chunk_indices;
    GLsizei chunk_surface_indices = 0, chunk_all_indices = 0;
    // Ulrich's simplified chunks (options.chunk_meshes), one per slot, each drawn on its own.
    struct ChunkSlot {
        gpu::GlBuffer indices;
        GLsizei surface = 0, all = 0;
        float max_deviation = 0.f; // metres
    };
    std::vector<ChunkSlot> chunk_slots;
    GLenum chunk_index_type = GL_UNSIGNED_INT;
    gpu::GlVertexArray chunk_mesh_vao; // its element buffer: the chunk being drawn
    gpu::ShaderProgram chunk_program, chunk_clip_program, chunk_capture_program,
        chunk_capture_clip_program;
    // Whole patches go through the tessellator only; patches reaching past the valid extent
    // also through terrain_clip.geom (exact clipping, walls). Each pass draws both groups.
    gpu::ShaderProgram terrain_program, terrain_clip_program, capture_program, capture_clip_program;
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
    // Requests, below everything the current frame needs, what the camera will need
    // `prefetch_frames` frames ahead if it keeps its velocity.
    void prefetch(const lod::Camera& camera, const lod::SelectionSettings& settings);
    size_t uploadPatch(const stream::DecodedPatch& patch, int slot,
                       const std::unordered_set<int>& pending_slots = {});
    size_t buildChunk(const stream::DecodedPatch& patch, int slot);
    // What uploading `patch` will send, at most (the per-frame budget plans with it).
    size_t plannedUploadBytes(const stream::DecodedPatch& patch) const
    {
        return textures->uploadBytes(patch) + (options.chunk_meshes ? worstChunkMeshBytes(n) : 0);
    }
    bool drawsChunkMeshes(const RenderSettings& s) const
    {
        return s.scheme == LodScheme::ChunkedLod && options.chunk_meshes;
    }
    void countTraffic(FrameStats& stats);
    void computeNormals(PatchId p, const std::unordered_set<int>& pending);
    PatchInstances writeInstances(const lod::Camera& camera, const lod::Selection& selection,
                                  const RenderSettings& settings);
    // Selection, residency and instance buffer for one frame; `used` receives `settings` with
    // the ε actually met (raised when the selection exceeded the slots), which the
    // tessellator must use too.
    PatchInstances beginFrame(const lod::Camera& camera, const RenderSettings& settings,
                              FrameStats& stats, RenderSettings& used)
    {
        const lod::Selection selection = prepare(camera, settings, stats);
        used = settings;
        used.epsilon_px = selection.epsilon_px;
        return writeInstances(camera, selection, settings);
    }
    void setFrameUniforms(const gpu::ShaderProgram& program, const lod::Camera& camera,
                          const RenderSettings& settings) const;
    // Calls draw(program, first, count) for the non-empty instance groups: whole patches with
    // the plain (or capture) program, partial ones with the clipping one.
    template <class Draw>
    void forEachGroup(const PatchInstances& r, const RenderSettings& s, Draw&& draw,
                      bool capture) const
    {
        const auto [whole, clip] = programsFor(s, capture);
        if (r.whole)
            draw(*whole, size_t(0), r.whole);
        if (r.partial)
            draw(*clip, r.whole, r.partial);
    }
    // The programs of the scheme in `s`: for whole patches and for clipped ones.
    std::array<const gpu::ShaderProgram*, 2> programsFor(const RenderSettings& s,
                                                         bool capture) const
    {
        if (s.scheme != LodScheme::Tessellation)
            return capture ? std::array{&chunk_capture_program, &chunk_capture_clip_program}
                           : std::array{&chunk_program, &chunk_clip_program};
        return capture ? std::array{&capture_program, &capture_clip_program}
                       : std::array{&terrain_program, &terrain_clip_program};
    }
    // Draws instances [first, first + count) of `r` with `program`, which is in use: one
    // instanced draw, or one draw per chunk for Ulrich's simplified chunks.
    void drawPatches(const gpu::ShaderProgram& program, const RenderSettings& s,
                     const PatchInstances& r, size_t first, size_t count) const
    {
        const GLint instance_offset = program.uniform("u_instance_offset");
        if (drawsChunkMeshes(s)) {
            glBindVertexArray(chunk_mesh_vao.id());
            for (size_t i = first; i < first + count; ++i) {
                const ChunkSlot& c = chunk_slots[size_t(r.records[i].layer)];
                glVertexArrayElementBuffer(chunk_mesh_vao.id(), c.indices.id());
                glUniform1i(instance_offset, GLint(i));
                glDrawElements(GL_TRIANGLES, s.skirts ? c.all : c.surface, chunk_index_type,
                               nullptr);
            }
            return;
        }
        glUniform1i(instance_offset, GLint(first));
        if (s.scheme == LodScheme::Tessellation) {
            glBindVertexArray(empty_vao.id());
            glPatchParameteri(GL_PATCH_VERTICES, 1);
            glDrawArraysInstanced(GL_PATCHES, 0, primitivesPerInstance(s), GLsizei(count));
        } else {
            glBindVertexArray(chunk_vao.id());
            glDrawElementsInstanced(GL_TRIANGLES,
                                    s.skirts ? chunk_all_indices : chunk_surface_indices,
                                    GL_UNSIGNED_INT, nullptr, GLsizei(count));
        }
    }
    void buildChunkMesh();
    int primitivesPerInstance(const RenderSettings& settings) const
    {
        return blocks_per_side * blocks_per_side + (settings.skirts ? 4 * blocks_per_side : 0);
    }
    lod::Selection prepare(const lod::Camera& camera, const RenderSettings& settings,
                           FrameStats& stats);
};

TerrainRenderer::Impl::Impl(const archive::ArchiveReader& r, const RendererOptions& o)
    : reader(r), options(o), quadtree(lod::PatchQuadtree::fromArchive(r)), slots(slotCount(r, o)),
      residency(r.geometry(), slots), loader(r, o.decoded_cache_patches), layout(r.blockLayout()),
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
    if (options.chunk_meshes) {
        chunk_slots.resize(size_t(slots));
        chunk_index_type = chunkIndexType(n);
    }

    // Chunk meshes are built from codes on the CPU.
    const bool gpu_reconstruction = options.streaming && options.gpu_reconstruction &&
                                    !options.chunk_meshes && reader.decodesResiduals(1);
    textures = std::make_unique<PatchTextures>(
        n, layout, block_levels, slots, quantization,
        gpu_reconstruction ? dynamic_cast<const ProgressiveCodec*>(&reader.codec()) : nullptr);
    if (options.streaming) {
        stream::StreamerOptions so = stream::StreamerOptions::forRamBudget(
            size_t(options.ram_budget_mb * 1024.0 * 1024.0), options.io_threads);
        so.residuals_for_gpu = gpu_reconstruction;
        so.chunk_tolerance = options.chunk_meshes ? options.chunk_tolerance : -1.0;
        streamer = std::make_unique<stream::PatchStreamer>(reader, so);
        // The root stays resident: the last resort of every fallback.
        const PatchId root{0, 0, 0};
        for (const lod::PatchResidency::Load& l : residency.update({root}, ++frame))
            uploadPatch(*loader.load(l.id), l.slot);
        computeNormals(root, {});
        textures->finishUploads();
    }
    using gpu::ShaderStage;
    terrain_program = gpu::ShaderProgram({{GL_VERTEX_SHADER, "terrain.vert"},
                                          {GL_TESS_CONTROL_SHADER, "terrain.tesc"},
                                          {GL_TESS_EVALUATION_SHADER, "terrain.tese"},
                                          {GL_FRAGMENT_SHADER, "terrain.frag"}});
    terrain_clip_program = gpu::ShaderProgram({{GL_VERTEX_SHADER, "terrain.vert"},
                                               {GL_TESS_CONTROL_SHADER, "terrain.tesc"},
                                               {GL_TESS_EVALUATION_SHADER, "terrain.tese"},
                                               {GL_GEOMETRY_SHADER, "terrain_clip.geom"},
                                               {GL_FRAGMENT_SHADER, "terrain.frag"}});
    const std::vector<std::string> varyings = {"Capture.tf_position", "Capture.tf_instance",
                                               "Capture.tf_skirt"};
    capture_program = gpu::ShaderProgram({{GL_VERTEX_SHADER, "terrain.vert"},
                                          {GL_TESS_CONTROL_SHADER, "terrain.tesc"},
                                          {GL_TESS_EVALUATION_SHADER, "terrain.tese"}},
                                         varyings);
    capture_clip_program = gpu::ShaderProgram({{GL_VERTEX_SHADER, "terrain.vert"},
                                               {GL_TESS_CONTROL_SHADER, "terrain.tesc"},
                                               {GL_TESS_EVALUATION_SHADER, "terrain.tese"},
                                               {GL_GEOMETRY_SHADER, "terrain_clip.geom"}},
                                              varyings);
    chunk_program = gpu::ShaderProgram(
        {{GL_VERTEX_SHADER, "chunk.vert"}, {GL_FRAGMENT_SHADER, "terrain.frag"}});
    chunk_clip_program = gpu::ShaderProgram({{GL_VERTEX_SHADER, "chunk.vert"},
                                             {GL_GEOMETRY_SHADER, "terrain_clip.geom"},
                                             {GL_FRAGMENT_SHADER, "terrain.frag"}});
    chunk_capture_program = gpu::ShaderProgram({{GL_VERTEX_SHADER, "chunk.vert"}}, varyings);
    chunk_capture_clip_program = gpu::ShaderProgram(
        {{GL_VERTEX_SHADER, "chunk.vert"}, {GL_GEOMETRY_SHADER, "terrain_clip.geom"}}, varyings);
    buildChunkMesh();
    sky_program =
        gpu::ShaderProgram({{GL_VERTEX_SHADER, "sky.vert"}, {GL_FRAGMENT_SHADER, "sky.frag"}});
}

void TerrainRenderer::Impl::buildChunkMesh()
{
    // The patch's cells as two triangles each (one diagonal: Err(P) holds for either), then
    // the skirt: a quad under each border cell, its first and last vertices feet (the capture
    // tests tell skirt triangles by their first vertex; shading reads the last).
    const GLuint C = GLuint(n - 1), N = GLuint(n);
    std::vector<GLuint> indices;
    indices.reserve(size_t(C) * C * 6 + size_t(4) * C * 6);
    for (GLuint j = 0; j < C; ++j)
        for (GLuint i = 0; i < C; ++i) {
            const GLuint a = j * N + i, b = a + 1, c = a + N, d = c + 1;
            indices.insert(indices.end(), {a, b, c, b, d, c});
        }
    chunk_surface_indices = GLsizei(indices.size());
    auto ring = [&](GLuint k) -> GLuint {
        if (k < C)
            return k; // north row
        if (k < 2 * C)
            return (k - C) * N + C; // east column
        if (k < 3 * C)
            return C * N + (C - (k - 2 * C)); // south row, east to west
        return (C - (k - 3 * C)) * N;         // west column, south to north
    };
    const GLuint R = 4 * C;
    for (GLuint k = 0; k < R; ++k) {
        const GLuint t0 = ring(k), t1 = ring((k + 1) % R);
        const GLuint f0 = N * N + k, f1 = N * N + (k + 1) % R;
        indices.insert(indices.end(), {f0, t0, t1, f0, t1, f1});
    }
    chunk_all_indices = GLsizei(indices.size());
    glNamedBufferStorage(chunk_indices.id(), GLsizeiptr(indices.size() * sizeof(GLuint)),
                         indices.data(), 0);
    glVertexArrayElementBuffer(chunk_vao.id(), chunk_indices.id());
    gpu::checkGlError("terrain renderer: chunk mesh");
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
        return textures->uploadBytes(patch) + (options.chunk_meshes ? buildChunk(patch, slot) : 0);
    }
    const int parent_slot = residency.slotOf(p.parent());
    if (parent_slot < 0 || pending_slots.count(parent_slot))
        throw Error(reader.describe(p) + ": internal: parent not resident for GPU reconstruction");
    textures->reconstruct(patch, parent_slot, slot, lambda_cap);
    return textures->uploadBytes(patch);
}

// Ulrich's chunk of `patch` into `slot`, simplified to chunk_tolerance·Err(P). Returns the
// bytes sent.
size_t TerrainRenderer::Impl::buildChunk(const stream::DecodedPatch& patch, int slot)
{
    // Streaming: the decode worker built it.
    std::optional<lod::ChunkMesh> built;
    const lod::ChunkMesh& mesh =
        patch.chunk ? *patch.chunk
                    : built.emplace(stream::patchChunk(reader, patch.id, patch.codes.data(),
                                                       options.chunk_tolerance));
    ChunkSlot& c = chunk_slots[size_t(slot)];
    // A new buffer: GL keeps the old one alive while a queued draw still reads it.
    c.indices = gpu::GlBuffer();
    size_t bytes = 0;
    if (chunk_index_type == GL_UNSIGNED_SHORT) {
        const std::vector<uint16_t> narrow(mesh.indices.begin(), mesh.indices.end());
        bytes = narrow.size() * sizeof(uint16_t);
        glNamedBufferStorage(c.indices.id(), GLsizeiptr(bytes), narrow.data(), 0);
    } else {
        bytes = mesh.indices.size() * sizeof(uint32_t);
        glNamedBufferStorage(c.indices.id(), GLsizeiptr(bytes), mesh.indices.data(), 0);
    }
    c.surface = GLsizei(mesh.surface_indices);
    c.all = GLsizei(mesh.indices.size());
    c.max_deviation = float(mesh.max_deviation * quantization.scale);
    return bytes;
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
                                                     const lod::Selection& selection,
                                                     const RenderSettings& settings)
{
    // Skirts hang by what the mesh drops beyond Err(P): the tessellator's λ, or the chunk's
    // simplification error.
    const bool chunks = drawsChunkMeshes(settings);
    PatchInstances built = buildPatchInstances(
        quadtree, selection, camera.position(), [&](PatchId p) { return residency.slotOf(p); },
        [&](PatchId p) {
            const int slot = residency.slotOf(p);
            return chunks ? double(chunk_slots[size_t(slot)].max_deviation)
                          : double(textures->lambdaMax(slot));
        },
        skirt_margin);
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
                                             const lod::Camera& camera,
                                             const RenderSettings& settings) const
{
    const GLuint id = program.id();
    setMatrix(program, "u_view_projection", reverseZProjection(camera) * camera.view());
    const CameraAnchor anchor = cameraAnchor(quadtree.frame(), camera.position());
    glProgramUniform2f(id, program.uniform("u_spacing"), float(quadtree.frame().spacingX()),
                       float(-quadtree.frame().spacingY()));
    glProgramUniform2f(id, program.uniform("u_anchor_offset"), float(anchor.x_rel),
                       float(anchor.y_rel));
    glProgramUniform2f(id, program.uniform("u_viewport"), float(camera.viewport().width),
                       float(camera.viewport().height));
    glProgramUniform1f(id, program.uniform("u_epsilon"), float(settings.epsilon_px));
    glProgramUniform1f(id, program.uniform("u_height_scale"), float(quantization.scale));
    glProgramUniform1f(id, program.uniform("u_height_offset"),
                       float(quantization.offset - camera.position().z));
    glProgramUniform1i(id, program.uniform("u_patch_cells"), n - 1);
    glProgramUniform1i(id, program.uniform("u_block_cells"), layout.block_cells);
    glProgramUniform1i(id, program.uniform("u_blocks_per_side"), blocks_per_side);
    glProgramUniform1i(id, program.uniform("u_block_levels"), block_levels);
    glProgramUniform1i(id, program.uniform("u_tessellation_rule"), int(settings.tessellation_rule));
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
}

lod::Selection TerrainRenderer::Impl::prepare(const lod::Camera& camera,
                                              const RenderSettings& settings, FrameStats& stats)
{
    textures->collect(); // λ maxima derived on the GPU in earlier frames
    auto t0 = std::chrono::steady_clock::now();
    lod::SelectionSettings ss;
    // Brute force: ε = 0 refines to the finest level wherever the frustum lets it.
    ss.epsilon_px = settings.scheme == LodScheme::BruteForce ? 0.0 : settings.epsilon_px;
    ss.cull = settings.cull;
    ss.max_patches = size_t(slots);
    if (drawsChunkMeshes(settings))
        ss.error_scale = 1.0 + options.chunk_tolerance;
    lod::Selection selection = quadtree.select(camera, ss);
    stats.cpu_select_ms = millisecondsSince(t0);
    stats.patches = int(selection.patches.size());
    stats.culled = selection.culled;
    stats.epsilon_px = selection.epsilon_px;
    t0 = std::chrono::steady_clock::now();
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

void TerrainRenderer::Impl::prefetch(const lod::Camera& camera,
                                     const lod::SelectionSettings& settings)
{
    const glm::dvec3 velocity = has_last_camera ? camera.position() - last_camera : glm::dvec3(0.0);
    last_camera = camera.position();
    has_last_camera = true;
    if (options.prefetch_frames <= 0 || glm::length(velocity) <= 0.0)
        return;
    // Within the coordinates a camera may take, however far a jump extrapolates.
    const double limit = lod::kCameraCoordinateRange.hi;
    const glm::dvec3 ahead =
        glm::clamp(camera.position() + velocity * double(options.prefetch_frames),
                   glm::dvec3(-limit), glm::dvec3(limit));
    const lod::Camera future(ahead, ahead + camera.forward(), glm::degrees(camera.fovY()),
                             camera.viewport(), camera.nearPlane(), camera.farPlane());
    const PyramidGeometry& g = reader.geometry();
    for (const lod::SelectedPatch& sp : quadtree.select(future, settings).patches)
        if (residency.slotOf(sp.id) < 0)
            streamer->request(sp.id, -1e7 + 1e6 * (g.levelCount() - sp.id.level) + sp.screen_error);
}

lod::Selection TerrainRenderer::Impl::streamResident(const lod::Selection& desired,
                                                     FrameStats& stats, const lod::Camera& camera,
                                                     const lod::SelectionSettings& settings)
{
    const PyramidGeometry& g = reader.geometry();
    const PatchId root{0, 0, 0};
    auto resident = [&](PatchId p) { return residency.slotOf(p) >= 0; };
    // Coarse before fine, then by screen-space error.
    auto priority = [&](const PatchId& p, double screen_error) {
        return 1e6 * (g.levelCount() - p.level) + screen_error;
    };
    streamer->beginFrame();
    for (auto& patch : streamer->takeReady())
        arrived.push_back(std::move(patch));
    std::unordered_map<int64_t, double> wanted; // patch index -> request priority
    for (const lod::SelectedPatch& sp : desired.patches)
        wanted[g.patchIndex(sp.id)] = priority(sp.id, sp.screen_error);
    // A patch reconstructed on the GPU needs its parent resident, so every ancestor up to the
    // finest resident one is wanted too, ahead of it: one request round for the whole chain.
    if (streamer->options().residuals_for_gpu) {
        std::vector<PatchId> chains;
        for (const auto& [key, pri] : wanted)
            chains.push_back(g.patchAt(key));
        for (PatchId p : chains)
            for (PatchId a = p; a.level > 0 && !resident(a);) {
                a = a.parent();
                if (!wanted.emplace(g.patchIndex(a), priority(a, 0.0)).second)
                    break; // the rest of the chain is in already
            }
    }
    for (const auto& [key, pri] : wanted)
        if (residency.slotOf(g.patchAt(key)) < 0)
            streamer->request(g.patchAt(key), pri);
    prefetch(camera, settings);
    const lod::ResidentCover before = lod::residentCover(desired, g, resident);

    // What this frame keeps: the root, what is drawn now, and the parents of patches waiting
    // to be reconstructed ("ancestors needed for decoding stay resident").
    std::vector<PatchId> needed;
    std::unordered_set<int64_t> in_needed;
    auto need = [&](PatchId p) {
        if (in_needed.insert(g.patchIndex(p)).second)
            needed.push_back(p);
    };
    need(root);
    for (const lod::SelectedPatch& d : before.patches)
        need(d.id);
    std::sort(arrived.begin(), arrived.end(), [](const auto& a, const auto& b) {
        return a->id.level < b->id.level; // parents before their children
    });
    for (const auto& patch : arrived)
        if (patch->needsGpuReconstruction() && wanted.count(g.patchIndex(patch->id)) &&
            resident(patch->id.parent()) && needed.size() < size_t(slots))
            need(patch->id.parent());

    // Uploads: arrived patches still wanted, within the per-frame budget and the free slots.
    const double budget_bytes = options.upload_budget_mb * 1024.0 * 1024.0;
    size_t planned_bytes = 0;
    std::vector<std::shared_ptr<const stream::DecodedPatch>> uploads, keep;
    std::unordered_set<int64_t> uploading;
    for (auto& patch : arrived) {
        const int64_t key = g.patchIndex(patch->id);
        if (!wanted.count(key) || resident(patch->id) || uploading.count(key))
            continue; // no longer wanted: the RAM cache still has it for a later request
        const bool parent_ready = !patch->needsGpuReconstruction() ||
                                  resident(patch->id.parent()) ||
                                  uploading.count(g.patchIndex(patch->id.parent()));
        const size_t bytes = plannedUploadBytes(*patch);
        const bool within_budget =
            uploads.empty() || (int(uploads.size()) < options.uploads_per_frame &&
                                double(planned_bytes + bytes) <= budget_bytes);
        if (parent_ready && within_budget && needed.size() < size_t(slots)) {
            planned_bytes += bytes;
            need(patch->id);
            uploads.push_back(patch);
            uploading.insert(key);
        } else {
            keep.push_back(patch);
        }
    }
    const auto loads = residency.update(needed, ++frame);
    std::unordered_map<int64_t, int> slot_of_load;
    std::unordered_set<int> pending_slots;
    for (const lod::PatchResidency::Load& l : loads) {
        slot_of_load[g.patchIndex(l.id)] = l.slot;
        pending_slots.insert(l.slot);
    }
    // Coarse first, so that a parent uploaded this frame is written before its children.
    const auto t0 = std::chrono::steady_clock::now();
    size_t done = 0;
    for (; done < uploads.size(); ++done) {
        if (done > 0 && millisecondsSince(t0) > options.upload_budget_ms)
            break; // the time budget: the rest waits for the next frame
        const auto& patch = uploads[done];
        const int slot = slot_of_load.at(g.patchIndex(patch->id));
        stats.bytes_uploaded += uploadPatch(*patch, slot, pending_slots);
        pending_slots.erase(slot);
        computeNormals(patch->id, pending_slots); // inside the time budget too
        stats.reconstructed += patch->needsGpuReconstruction();
    }
    for (size_t k = done; k < uploads.size(); ++k) {
        residency.release(uploads[k]->id); // assigned but never written
        keep.push_back(uploads[k]);
    }
    arrived.swap(keep);
    if (done > 0)
        textures->finishUploads();
    stats.loaded = int(done);
    stats.resident = residency.residentCount();

    const lod::ResidentCover cover = lod::residentCover(desired, g, resident);
    stats.missing = cover.missing;
    lod::Selection drawn = desired;
    drawn.patches = cover.patches;
    return drawn;
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

FrameStats TerrainRenderer::draw(const lod::Camera& camera, const RenderSettings& settings)
{
    settings.validate();
    Impl& m = *impl_;
    FrameStats stats;
    RenderSettings s;
    const PatchInstances ranges = m.beginFrame(camera, settings, stats, s);

    glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
    glClearColor(s.clear_colour.r, s.clear_colour.g, s.clear_colour.b, s.clear_colour.a);
    glClearDepth(0.0);
    glDepthMask(GL_TRUE);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glDisable(GL_CULL_FACE);

    const glm::vec3 horizon(0.78f, 0.84f, 0.90f), zenith(0.30f, 0.48f, 0.75f);
    const glm::dmat4 view_projection = reverseZProjection(camera) * camera.view();
    if (s.sky) {
        glDisable(GL_DEPTH_TEST);
        m.sky_program.use();
        setMatrix(m.sky_program, "u_inverse_view_projection", glm::inverse(view_projection));
        glUniform3f(m.sky_program.uniform("u_horizon_colour"), horizon.r, horizon.g, horizon.b);
        glUniform3f(m.sky_program.uniform("u_zenith_colour"), zenith.r, zenith.g, zenith.b);
        glBindVertexArray(m.empty_vao.id());
        glDrawArrays(GL_TRIANGLES, 0, 3);
    }

    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_GREATER);
    const glm::dvec3 sun = glm::normalize(s.sun_direction);
    // Fog thickens over the terrain's own size: a tenth of the light lost across it.
    const double extent = std::max(m.quadtree.frame().extentX(), m.quadtree.frame().extentY());
    for (const gpu::ShaderProgram* p : m.programsFor(s, false)) {
        const GLuint id = p->id();
        m.setFrameUniforms(*p, camera, s);
        glProgramUniform3f(id, p->uniform("u_sun_direction"), float(sun.x), float(sun.y),
                           float(sun.z));
        glProgramUniform2f(id, p->uniform("u_height_range"),
                           float(m.min_height - camera.position().z),
                           float(m.max_height - camera.position().z));
        glProgramUniform1f(id, p->uniform("u_sea_level"), float(-camera.position().z));
        glProgramUniform3f(id, p->uniform("u_fog_colour"), horizon.r, horizon.g, horizon.b);
        glProgramUniform1f(id, p->uniform("u_fog_density"),
                           s.fog ? float(0.105 / std::max(extent, 1.0)) : 0.f);
        glProgramUniform1i(id, p->uniform("u_block_cells_f"), m.layout.block_cells);
        glProgramUniform3f(id, p->uniform("u_flat_colour"), 0.05f, 0.05f, 0.08f);
    }
    // Both instance groups with `mode` (3: the wireframe's flat colour).
    auto drawTerrain = [&](int mode) {
        m.forEachGroup(
            ranges, s,
            [&](const gpu::ShaderProgram& p, size_t first, size_t n) {
                p.use();
                glUniform1i(p.uniform("u_mode"), mode);
                m.drawPatches(p, s, ranges, first, n);
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
        glPolygonOffset(1.f, 1.f); // reverse-Z: larger depth is nearer
        glDepthFunc(GL_GEQUAL);
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
    return stats;
}

CapturedSurface TerrainRenderer::capture(const lod::Camera& camera, const RenderSettings& settings)
{
    settings.validate();
    Impl& m = *impl_;
    FrameStats stats;
    RenderSettings s;
    const PatchInstances ranges = m.beginFrame(camera, settings, stats, s);
    CapturedSurface out;
    out.camera_position = camera.position();
    out.patches = ranges.patches;
    for (const GpuPatchInstance& r : ranges.records)
        out.skirt_depth.push_back(r.skirt_depth);
    if (ranges.total() == 0)
        return out;

    for (const gpu::ShaderProgram* p : m.programsFor(s, true))
        m.setFrameUniforms(*p, camera, s);
    GLint previous_framebuffer = 0;
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &previous_framebuffer);
    if (!m.capture_target)
        m.capture_target = std::make_unique<gpu::RenderTarget>(1, 1, 1);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, m.capture_target->framebuffer());
    glEnable(GL_RASTERIZER_DISCARD);
    // A block yields at most 2·b² triangles plus its transition ring, a skirt segment 4·b;
    // clipping makes at most 3 triangles and 2 walls (4 triangles) of one.
    const size_t b = size_t(m.layout.block_cells);
    const size_t per_instance =
        std::max<size_t>(size_t(m.blocks_per_side) * m.blocks_per_side * (2 * b * b + 8 * b) +
                             (s.skirts ? size_t(4) * m.blocks_per_side * (4 * b + 4) : 0),
                         size_t(m.chunk_all_indices) / 3);
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
        ranges, s,
        [&](const gpu::ShaderProgram& p, size_t first, size_t n) {
            p.use();
            const GLintptr offset = GLintptr(stored_total * 3 * sizeof(CapturedVertex));
            glBindBufferRange(GL_TRANSFORM_FEEDBACK_BUFFER, 0, m.feedback.id(), offset,
                              GLsizeiptr(m.feedback_capacity - size_t(offset)));
            glBeginQuery(GL_TRANSFORM_FEEDBACK_PRIMITIVES_WRITTEN, m.written.id());
            glBeginQuery(GL_PRIMITIVES_GENERATED, m.primitives.id());
            glBeginTransformFeedback(GL_TRIANGLES);
            m.drawPatches(p, s, ranges, first, n);
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

double TerrainRenderer::groundHeight(double x, double y) const
{
    return impl_->coarse->groundHeight(x, y);
}

void TerrainRenderer::clipPlanesFor(glm::dvec3 position, double& near_m, double& far_m) const
{
    impl_->coarse->clipPlanesFor(position, near_m, far_m);
}

lod::Camera TerrainRenderer::defaultCamera(lod::Viewport viewport, double fov_y_degrees) const
{
    return impl_->coarse->defaultCamera(viewport, fov_y_degrees);
}

} // namespace ridge::render
