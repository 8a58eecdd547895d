// Scheme "rings": the rings structure of Erra, Scarano & Guida (§4–6). The policy —
// updateRings, orientations, the stitch table, the streaming cover — is plain C++
// (lod::RingsSelector, ridge/lod/rings.h); this is its GL half: the static vertex grids, one
// per level, built once (each vertex the paper's (x, y_pos, z, w_odd)), the tiles' records,
// and shaders/rings.vert, which stitches edges towards coarser rings. No skirts: the seams are
// closed by the stitching itself (SchemePromises::Seams::Stitching), and no screen-space bound
// is promised (rings choose levels by distance, not by error).
#include "../record_buffer.h"
#include "../scheme_programs.h"
#include "../terrain_scheme.h"

#include "ridge/core/error.h"
#include "ridge/lod/rings.h"
#include "ridge/lod/screen_space_error.h"

#include <algorithm>
#include <map>

namespace ridge::render {
namespace {

// std430 mirror of RingsTile in shaders/rings.vert.
struct RingsTileRecord {
    int32_t sample_offset[2];
    int32_t coarse_offset[2];
    int32_t coarse_layer;
    int32_t stitch; // bit 16: orientation in bits 0..3 (looked up in the table); else the mask
    int32_t cells;
    int32_t pad;
};
static_assert(sizeof(RingsTileRecord) == 32, "must match the std430 layout of RingsTile");

constexpr int32_t kByTable = 1 << 16;

// One static grid of c × c cells: vertices (x, z, y_pos, w_odd) as 16-bit integers, and two
// triangles a cell (a b c, b d c: the diagonal of the other grids).
class RingsGrid {
  public:
    explicit RingsGrid(int cells) : cells_(cells)
    {
        const int n = cells + 1;
        std::vector<int16_t> vertices;
        vertices.reserve(size_t(n) * n * 4);
        for (int z = 0; z < n; ++z)
            for (int x = 0; x < n; ++x) {
                const lod::EdgePosition pos = positionOf(x, z, cells);
                // Odd along its edge: the column on the up and down edges, the row on the
                // right and left ones.
                const bool horizontal =
                    pos == lod::EdgePosition::Up || pos == lod::EdgePosition::Down;
                const int along = horizontal ? x : z;
                vertices.insert(vertices.end(),
                                {int16_t(x), int16_t(z), int16_t(pos), int16_t(along % 2)});
            }
        std::vector<uint32_t> indices;
        indices.reserve(size_t(cells) * cells * 6);
        for (int z = 0; z < cells; ++z)
            for (int x = 0; x < cells; ++x) {
                const uint32_t a = uint32_t(z * n + x), b = a + 1, c = a + uint32_t(n), d = c + 1;
                indices.insert(indices.end(), {a, b, c, b, d, c});
            }
        count_ = GLsizei(indices.size());
        glNamedBufferStorage(vertices_.id(), GLsizeiptr(vertices.size() * sizeof(int16_t)),
                             vertices.data(), 0);
        glNamedBufferStorage(indices_.id(), GLsizeiptr(indices.size() * sizeof(uint32_t)),
                             indices.data(), 0);
        glVertexArrayVertexBuffer(vao_.id(), 0, vertices_.id(), 0, 4 * sizeof(int16_t));
        glVertexArrayAttribIFormat(vao_.id(), 0, 4, GL_SHORT, 0);
        glVertexArrayAttribBinding(vao_.id(), 0, 0);
        glEnableVertexArrayAttrib(vao_.id(), 0);
        glVertexArrayElementBuffer(vao_.id(), indices_.id());
        gpu::checkGlError("rings: static grid");
    }

    static lod::EdgePosition positionOf(int x, int z, int cells)
    {
        using E = lod::EdgePosition;
        const bool up = z == 0, down = z == cells, left = x == 0, right = x == cells;
        if (up && left)
            return E::UpLeft;
        if (up && right)
            return E::UpRight;
        if (down && right)
            return E::DownRight;
        if (down && left)
            return E::DownLeft;
        return up ? E::Up : right ? E::Right : down ? E::Down : left ? E::Left : E::Inside;
    }

    void draw(size_t count) const
    {
        glBindVertexArray(vao_.id());
        glDrawElementsInstanced(GL_TRIANGLES, count_, GL_UNSIGNED_INT, nullptr, GLsizei(count));
    }
    size_t triangles() const { return size_t(count_) / 3; }
    int cells() const { return cells_; }

  private:
    int cells_;
    GLsizei count_ = 0;
    gpu::GlVertexArray vao_;
    gpu::GlBuffer vertices_, indices_;
};

class RingsScheme final : public TerrainScheme {
  public:
    RingsScheme(const SchemeResources& r, const lod::RingsSettings& settings)
        : quadtree_(r.quadtree), residency_(r.residency), selector_(r.quadtree, settings),
          programs_(r, {{GL_VERTEX_SHADER, "rings.vert"}})
    {
        const lod::RingsStructure& s = selector_.structure();
        for (int level = 0; level <= s.finestLevel(); ++level) {
            const int c = s.cellsAt(level);
            if (!grids_.count(c))
                grids_.emplace(c, std::make_unique<RingsGrid>(c));
        }
    }

    lod::PatchSelector* selector() override { return &selector_; }

    bool buildInstances(const lod::Camera& camera, const RenderSettings& settings,
                        PatchInstances& out) override
    {
        const lod::RingsStructure& s = selector_.structure();
        const PyramidGeometry& g = quadtree_.geometry();
        const int F = s.finestLevel(), C = g.cells(), d = s.vertexStep();
        const double k = settings.exaggeration;
        const glm::dvec3 eye = camera.position();
        const CameraAnchor anchor = cameraAnchor(quadtree_.frame(), eye);
        const std::vector<lod::RingTile>& tiles = selector_.drawnTiles();
        order_.clear();
        for (size_t t = 0; t < tiles.size(); ++t) {
            const lod::RingTile& tile = tiles[t];
            const PatchId own = selector_.ancestorOf(tile.x, tile.y, tile.level);
            const int shift = F - tile.level;
            const double offset_x = double(((tile.x - (own.x << shift)) * C) >> shift);
            const double offset_y = double(((tile.y - (own.y << shift)) * C) >> shift);
            const int cells = s.cellsAt(tile.level);
            const bool partial = offset_x + cells * d > g.validExtentX(own) ||
                                 offset_y + cells * d > g.validExtentY(own);
            float lo = 0.f, hi = 0.f;
            s.tileBounds(tile.x, tile.y, lo, hi);
            const lod::Box box =
                quadtree_.frame().patchBox(PatchId{F, tile.x, tile.y}, k * lo, k * hi);
            order_.push_back({partial, cells, lod::distanceToBox(eye, box), t});
        }
        // Whole tiles first (the clipping draw takes the rest), by grid within each group so
        // that one draw call covers a run of one grid, front to back within a grid.
        std::sort(order_.begin(), order_.end(), [](const OrderEntry& a, const OrderEntry& b) {
            if (a.partial != b.partial)
                return !a.partial;
            if (a.cells != b.cells)
                return a.cells > b.cells;
            return a.distance < b.distance;
        });
        out = PatchInstances{};
        records_.clear();
        cells_.clear();
        for (const OrderEntry& e : order_) {
            const lod::RingTile& tile = tiles[e.tile];
            const int shift = F - tile.level;
            const PatchId own = selector_.ancestorOf(tile.x, tile.y, tile.level);
            const int slot = residency_.slotOf(own);
            if (slot < 0)
                throw Error("rings: internal: tile patch not resident");
            float lo = 0.f, hi = 0.f;
            s.tileBounds(tile.x, tile.y, lo, hi);
            GpuPatchInstance r{};
            r.origin[0] = int32_t(int64_t(tile.x) * C - anchor.column);
            r.origin[1] = int32_t(int64_t(tile.y) * C - anchor.row);
            r.step = int32_t((int64_t{1} << shift) * d);
            r.layer = slot;
            r.level = tile.level;
            r.err = float(k * double(quadtree_.bounds(own).err));
            // No skirts; a wall under the terrain's clipped border hangs this deep.
            r.skirt_depth = float(k * double(hi - lo) + 1.0);
            r.valid_extent[0] = float(g.validExtentX(own));
            r.valid_extent[1] = float(g.validExtentY(own));
            r.min_z = float(k * double(lo) - eye.z);
            r.max_z = float(k * double(hi) - eye.z);
            RingsTileRecord rr{};
            rr.sample_offset[0] = ((tile.x - (own.x << shift)) * C) >> shift;
            rr.sample_offset[1] = ((tile.y - (own.y << shift)) * C) >> shift;
            rr.coarse_layer = -1;
            if (tile.stitch) {
                const PatchId coarse = selector_.ancestorOf(tile.x, tile.y, tile.level - 1);
                rr.coarse_layer = residency_.slotOf(coarse);
                if (rr.coarse_layer < 0)
                    throw Error("rings: internal: coarser patch not resident");
                rr.coarse_offset[0] = ((tile.x - (coarse.x << (shift + 1))) * C) >> (shift + 1);
                rr.coarse_offset[1] = ((tile.y - (coarse.y << (shift + 1))) * C) >> (shift + 1);
            }
            rr.stitch = tile.by_table ? kByTable | int32_t(tile.orientation) : int32_t(tile.stitch);
            rr.cells = e.cells;
            out.records.push_back(r);
            out.patches.push_back(own);
            records_.push_back(rr);
            cells_.push_back(e.cells);
            (e.partial ? out.partial : out.whole) += 1;
        }
        return true;
    }

    size_t beginDraw(const SchemeFrame&) override { return buffer_.upload(records_); }

    // No skirts: nothing hangs below a tile's border.
    double meshDeviation(int) const override { return 0.0; }

    std::array<const gpu::ShaderProgram*, 2> programs(bool capture, bool fading,
                                                      const RenderSettings&) override
    {
        return programs_.get(capture, fading);
    }

    void setUniforms(const gpu::ShaderProgram& program, const SchemeFrame&) const override
    {
        GLint table[9];
        for (size_t k = 0; k < 9; ++k)
            table[k] = lod::kStitchTable[k];
        glProgramUniform1iv(program.id(), program.uniform("u_stitch_table"), 9, table);
        glProgramUniform1i(program.id(), program.uniform("u_vertex_step"),
                           selector_.structure().vertexStep());
    }

    // Runs of one grid within [first, first + count): one instanced draw each.
    void draw(const gpu::ShaderProgram& program, const SchemeFrame&, size_t first,
              size_t count) const override
    {
        buffer_.bind(3);
        for (size_t begin = first, end = first + count; begin < end;) {
            size_t run = begin + 1;
            while (run < end && cells_[run] == cells_[begin])
                ++run;
            glUniform1i(program.uniform("u_instance_offset"), GLint(begin));
            grids_.at(cells_[begin])->draw(run - begin);
            begin = run;
        }
    }

    // The finest grid's triangles (degenerate ones included: capture stores them too).
    size_t maxTrianglesPerInstance(bool) const override
    {
        return grids_.rbegin()->second->triangles(); // keyed by cells: the last is the finest
    }

  private:
    struct OrderEntry {
        bool partial;
        int cells;
        double distance;
        size_t tile;
    };
    const lod::PatchQuadtree& quadtree_;
    const lod::PatchResidency& residency_;
    lod::RingsSelector selector_;
    std::map<int, std::unique_ptr<RingsGrid>> grids_; // by cells a side
    std::vector<OrderEntry> order_;
    std::vector<RingsTileRecord> records_;
    std::vector<int> cells_; // per record
    RecordBuffer<RingsTileRecord> buffer_;
    SchemePrograms programs_;
};

constexpr const char* kRings = "rings";
constexpr const char* kVertexStep = "vertex-step";

// The rings' settings from the scheme's options, refused with the archive's name when its
// patches cannot make the static grids.
lod::RingsSettings settingsFor(const archive::ArchiveReader& reader, const SchemeOptions& own)
{
    lod::RingsSettings settings;
    settings.rings = int(own.integer(kRings));
    settings.vertex_step = int(own.integer(kVertexStep));
    try {
        settings.validate(reader.geometry());
    } catch (const Error& e) {
        throw Error(reader.path() + ": --lod " + own.spec() + ": " + e.what());
    }
    return settings;
}

} // namespace

SchemeInfo ringsScheme()
{
    return {
        .name = "rings",
        .description = "the fractal-rings paper's rings of tiles around the viewer, one level "
                       "coarser a ring, stitched odd/even (no skirts, no screen-space bound)",
        .options = {SchemeOption::integer(kRings,
                                          "rings around the central patch, each one level "
                                          "coarser than the one inside it (0: one per level)",
                                          0, lod::RingsSettings::kMaxRings, 0),
                    SchemeOption::integer(kVertexStep,
                                          "samples per vertex along a side: 1, or 2 as the "
                                          "paper's 128² vertices for 256² tiles",
                                          1, 2, 1)},
        .needs =
            [](const archive::ArchiveReader& reader, const lod::TerrainFrame& frame,
               const RendererOptions&, const SchemeOptions& own) {
                settingsFor(reader, own);
                try {
                    lod::ringsWrapTiles(frame); // a globe's turn in whole tiles
                } catch (const Error& e) {
                    throw Error(reader.path() + ": --lod " + own.spec() + ": " + e.what());
                }
                return SchemeNeeds{};
            },
        .make = [](const SchemeResources& r) -> std::unique_ptr<TerrainScheme> {
            return std::make_unique<RingsScheme>(r, settingsFor(r.reader, r.own));
        },
        // Arrivals are not faded: tiles meet at stitched vertices with no skirt, so one tile
        // fading alone would open its seams.
        // Rings wrap with the globe when its turn is whole tiles (lod::ringsWrapTiles; needs
        // refuses the archive otherwise).
        .promises = {.screen_space_error = false,
                     .seams = SchemePromises::Seams::Stitching,
                     .pop_free = false,
                     .wrapping_globe = true,
                     .arrivals = SchemePromises::Arrivals::Replace},
    };
}

} // namespace ridge::render
