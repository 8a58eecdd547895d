// Scheme "chunked": Ulrich's chunked LOD ("Rendering massive terrains using chunked level of
// detail", 2000), the baseline of the hardware-tessellation paper. Each selected patch is one
// precomputed mesh of its level with a skirt around it. With its option meshes=on (the
// default) the mesh is simplified to tolerance·Err(P) (lod::buildChunkMesh, built on the
// stream workers), selection runs at (1 + tolerance)·Err(P) so ε still holds, and every chunk
// is its own draw call (no instancing: the paper's baseline). With meshes=off every patch
// draws its full grid of samples, all in one instanced draw.
#include "../patch_grid_mesh.h"
#include "../scheme_programs.h"
#include "../terrain_scheme.h"

#include "ridge/lod/chunk_mesh.h"

namespace ridge::render {
namespace {

// The options (SchemeInfo::options below): Ulrich's simplified chunks or full grids, and how
// far chunks are simplified. k in k·Err(P): 0 keeps every sample; beyond 100·Err(P) every
// chunk is already as coarse as its two triangles.
constexpr const char* kMeshes = "meshes";
constexpr const char* kTolerance = "tolerance";
constexpr ValueRange kToleranceRange = ValueRange::closed(0.0, 100.0);
static_assert(kToleranceRange.hi + 1.0 <= lod::SelectionSettings::kErrorScaleRange.hi,
              "the selection's error scale reaches 1 + the largest tolerance");

// Vertex ids run to n² + 4(n − 1) (the skirt's feet); 16-bit while they fit.
bool shortIndices(int n)
{
    return int64_t(n) * n + 4 * int64_t(n - 1) <= 65536;
}

// The index buffer of an unsimplified chunk: two triangles per cell, two per border cell of
// the skirt — what one slot must hold at most.
size_t worstChunkMeshBytes(int n)
{
    const size_t c = size_t(n - 1);
    return (6 * c * c + 24 * c) * (shortIndices(n) ? 2 : 4);
}

// Ulrich's chunk of one patch, as the stream workers build it.
struct PreparedChunk final : stream::PatchProduct {
    lod::ChunkMesh mesh;
    size_t bytes() const override { return sizeof(*this) + mesh.indices.size() * sizeof(uint32_t); }
};

// The chunk of patch `p` from its decoded codes: simplified to tolerance·Err(P), within the
// patch's valid extent. On a globe a triangle's sag below the curved surface beyond that of
// one cell (which the selection counts for every scheme: straight_cells 1) counts towards
// the tolerance too.
std::shared_ptr<const stream::PatchProduct> prepareChunk(const archive::ArchiveReader& reader,
                                                         const lod::TerrainFrame& frame,
                                                         double tolerance, PatchId p,
                                                         const uint16_t* codes)
{
    const PyramidGeometry& g = reader.geometry();
    const double scale = reader.quantization().scale;
    const double step = double(g.step(p.level));
    lod::ChunkSag sag;
    if (frame.onEllipsoid())
        sag = [&frame, step, scale](int cells) {
            return (frame.chordSag(cells * step) - frame.chordSag(step)) / scale;
        };
    auto out = std::make_shared<PreparedChunk>();
    out->mesh = lod::buildChunkMesh(codes, g.patchSize(), tolerance * reader.record(p).err / scale,
                                    g.coveredCellsX(p), g.coveredCellsY(p), sag);
    return out;
}

class ChunkedScheme final : public TerrainScheme {
  public:
    explicit ChunkedScheme(const SchemeResources& r)
        : textures_(r.textures), meshes_(r.own.flag(kMeshes)), product_(r.product),
          tolerance_(r.own.number(kTolerance)), scale_(r.reader.quantization().scale),
          n_(r.reader.geometry().patchSize()), grid_(n_),
          programs_(r, {{GL_VERTEX_SHADER, "chunk.vert"}})
    {
        if (meshes_)
            slots_.resize(size_t(r.slots));
    }

    void adjustSelection(const RenderSettings&, lod::SelectionSettings& s) const override
    {
        // The chunk drops up to tolerance·Err(P) more, its triangles' sag on a globe beyond
        // one cell's included (prepareChunk); one cell's sag is the selection's own.
        if (meshes_)
            s.error_scale = 1.0 + tolerance_;
    }

    size_t upload(const stream::DecodedPatch& patch, int slot) override
    {
        if (!meshes_)
            return 0;
        const auto& chunk = static_cast<const PreparedChunk&>(*patch.prepared.at(size_t(product_)));
        const lod::ChunkMesh& mesh = chunk.mesh;
        Slot& c = slots_[size_t(slot)];
        // A new buffer: GL keeps the old one alive while a queued draw still reads it.
        c.indices = gpu::GlBuffer();
        size_t bytes = 0;
        if (shortIndices(n_)) {
            const std::vector<uint16_t> narrow(mesh.indices.begin(), mesh.indices.end());
            bytes = narrow.size() * sizeof(uint16_t);
            glNamedBufferStorage(c.indices.id(), GLsizeiptr(bytes), narrow.data(), 0);
        } else {
            bytes = mesh.indices.size() * sizeof(uint32_t);
            glNamedBufferStorage(c.indices.id(), GLsizeiptr(bytes), mesh.indices.data(), 0);
        }
        c.surface = GLsizei(mesh.surface_indices);
        c.all = GLsizei(mesh.indices.size());
        c.max_deviation = float(mesh.max_deviation * scale_);
        return bytes;
    }
    size_t plannedUploadBytes(const stream::DecodedPatch&) const override
    {
        return meshes_ ? worstChunkMeshBytes(n_) : 0;
    }

    // Simplified chunks drop up to their own measured deviation; full grids keep every sample
    // but hang by λ as before (the skirt depth the baseline was measured with).
    double meshDeviation(int slot) const override
    {
        return meshes_ ? double(slots_[size_t(slot)].max_deviation)
                       : double(textures_.lambdaMax(slot));
    }

    std::array<const gpu::ShaderProgram*, 2> programs(bool capture, bool fading,
                                                      const RenderSettings&) override
    {
        return programs_.get(capture, fading);
    }

    void draw(const gpu::ShaderProgram& program, const SchemeFrame& frame, size_t first,
              size_t count) const override
    {
        const GLint instance_offset = program.uniform("u_instance_offset");
        const bool skirts = frame.settings.skirts;
        if (!meshes_) {
            glUniform1i(instance_offset, GLint(first));
            grid_.draw(count, skirts);
            return;
        }
        glBindVertexArray(mesh_vao_.id());
        const GLenum type = shortIndices(n_) ? GL_UNSIGNED_SHORT : GL_UNSIGNED_INT;
        for (size_t i = first; i < first + count; ++i) {
            glUniform1i(instance_offset, GLint(i));
            if (frame.instances.records[i].stand_in) {
                // A stand-in at its full grid: what arrives fades from it exactly.
                grid_.draw(1, skirts);
                glBindVertexArray(mesh_vao_.id());
                continue;
            }
            const Slot& c = slots_[size_t(frame.instances.records[i].layer)];
            glVertexArrayElementBuffer(mesh_vao_.id(), c.indices.id());
            glDrawElements(GL_TRIANGLES, skirts ? c.all : c.surface, type, nullptr);
        }
    }

    size_t maxTrianglesPerInstance(bool skirts) const override
    {
        return grid_.trianglesPerInstance(skirts); // a chunk never has more than its grid
    }

  private:
    struct Slot {
        gpu::GlBuffer indices;
        GLsizei surface = 0, all = 0;
        float max_deviation = 0.f; // metres
    };
    const PatchTextures& textures_;
    bool meshes_;
    int product_;
    double tolerance_, scale_;
    int n_;
    PatchGridMesh grid_;
    std::vector<Slot> slots_;
    gpu::GlVertexArray mesh_vao_; // its element buffer: the chunk being drawn
    SchemePrograms programs_;
};

SchemeNeeds chunkedNeeds(const archive::ArchiveReader& reader, const lod::TerrainFrame& frame,
                         const RendererOptions&, const SchemeOptions& own)
{
    SchemeNeeds needs;
    if (!own.flag(kMeshes))
        return needs;
    // Meshes are built from codes on the CPU, so streaming decodes on the CPU; each slot's
    // budget counts the worst-case (unsimplified) index buffer.
    needs.codes_on_cpu = true;
    needs.slot_bytes = double(worstChunkMeshBytes(reader.geometry().patchSize()));
    const double tolerance = own.number(kTolerance);
    // The renderer's frame: whether chunks sag.
    needs.preparation = [&reader, frame, tolerance](PatchId p, const uint16_t* codes) {
        return prepareChunk(reader, frame, tolerance, p, codes);
    };
    return needs;
}

} // namespace

SchemeInfo chunkedScheme()
{
    return {
        .name = "chunked",
        .description = "Ulrich's chunked LOD: one mesh per selected patch, with skirts",
        .options = {SchemeOption::flag(kMeshes,
                                       "Ulrich's chunks, simplified to tolerance·Err(P) on the "
                                       "stream workers (decoding on the CPU), one draw each; "
                                       "off: every patch's full grid, one instanced draw",
                                       true),
                    SchemeOption::number(kTolerance,
                                         "with meshes: simplify each chunk to tolerance·Err(P) "
                                         "and select at (1 + tolerance)·Err(P)",
                                         kToleranceRange,
                                         0.5)}, // fewest triangles and draws on the Sierra fly-over
        .needs = chunkedNeeds,
        .make = [](const SchemeResources& r) -> std::unique_ptr<TerrainScheme> {
            return std::make_unique<ChunkedScheme>(r);
        },
    };
}

} // namespace ridge::render
