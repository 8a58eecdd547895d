// Scheme "clipmaps": GPU-based geometry clipmaps as the clipmaps thesis builds them (chapter 3,
// after Asirvatham & Hoppe). The policy — level windows, level shifts, deactivation, the
// pending writes per level and the footprints — is plain C++ (lod::ClipmapSelector,
// lod/clipmap.h, lod/clipmap_footprints.h); this is its GL half:
//   - one RG16UI texture array of L layers of N × N texels (N = n + 1), the level windows,
//     addressed toroidally and filled on the GPU from the resident patch textures
//     (shaders/clipmap_fill.comp) by the writes the policy hands out: a level shift writes its
//     L-shaped strip, nothing else moves, and the render thread never waits — a write waits
//     for its patch, the level waits for its writes, the coarser level shows meanwhile;
//   - the footprints as constant vertex and 16-bit index buffers, one instanced draw per
//     footprint kind and instance group, finest levels first (§3.5.4), with frustum culling
//     per piece against the boxes of the patches under it;
//   - shaders/clipmaps.vert (heights from the level texture, the transition region blending
//     into the coarser level) and its own fragment stage, shaders/clipmaps.frag (shading from
//     the level textures).
// Positions go through framePoint like every scheme's (an integer offset from the anchor
// sample near the camera): the thesis's 3-D vertex textures and their float precision limit
// (§3.4) are not needed, on the plane or on the ellipsoid. No skirts: the perimeter triangles
// and the transition regions close the seams between levels (SchemePromises::Seams::
// Stitching), and the terrain's border is cut by the clip stage with a wall under it.
#include "../record_buffer.h"
#include "../scheme_programs.h"
#include "../terrain_scheme.h"

#include "ridge/core/error.h"
#include "ridge/lod/clipmap_footprints.h"
#include "ridge/lod/clipmap_selector.h"
#include "ridge/lod/frustum.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace ridge::render {
namespace {

// std430 mirror of ClipmapPiece in shaders/clipmaps.vert.
struct ClipmapPieceRecord {
    int32_t texel[2];        // texel of the window's sample (0, 0) in the level's texture
    int32_t coarse_texel[2]; // that sample's texel in the coarser level's texture
    float viewer[2];         // the viewer (window centre) in the window's cells
    int32_t local[2];        // the piece's vertex (0, 0) in the window's cells
    int32_t coarse_layer;    // −1: the coarsest drawn level
    int32_t kind;            // lod::FootprintKind
};
static_assert(sizeof(ClipmapPieceRecord) == 40, "must match the std430 layout of ClipmapPiece");

// A piece's valid extent on a side it is not clipped on (terrain_clip.geom's
// u_unclipped_extent).
constexpr float kUnclipped = 1e9f;

// x mod N for N a power of two, whatever x's sign.
int32_t wrapTexel(int64_t x, int N)
{
    return int32_t(x & int64_t(N - 1));
}

// One footprint's constant buffers: (x, y) as two 16-bit integers, 16-bit indices.
class FootprintMesh {
  public:
    explicit FootprintMesh(const lod::Footprint& f) : count_(GLsizei(f.indices.size()))
    {
        glNamedBufferStorage(vertices_.id(), GLsizeiptr(f.vertices.size() * sizeof(uint16_t)),
                             f.vertices.data(), 0);
        glNamedBufferStorage(indices_.id(), GLsizeiptr(f.indices.size() * sizeof(uint16_t)),
                             f.indices.data(), 0);
        glVertexArrayVertexBuffer(vao_.id(), 0, vertices_.id(), 0, 2 * sizeof(uint16_t));
        glVertexArrayAttribIFormat(vao_.id(), 0, 2, GL_UNSIGNED_SHORT, 0);
        glVertexArrayAttribBinding(vao_.id(), 0, 0);
        glEnableVertexArrayAttrib(vao_.id(), 0);
        glVertexArrayElementBuffer(vao_.id(), indices_.id());
        gpu::checkGlError("clipmaps: footprint");
    }
    void draw(size_t instances) const
    {
        glBindVertexArray(vao_.id());
        glDrawElementsInstanced(GL_TRIANGLES, count_, GL_UNSIGNED_SHORT, nullptr,
                                GLsizei(instances));
    }
    size_t triangles() const { return size_t(count_) / 3; }

  private:
    GLsizei count_;
    gpu::GlVertexArray vao_;
    gpu::GlBuffer vertices_, indices_;
};

class ClipmapsScheme final : public TerrainScheme {
  public:
    ClipmapsScheme(const SchemeResources& r, const lod::ClipmapSettings& settings)
        : quadtree_(r.quadtree), textures_(r.textures), residency_(r.residency),
          selector_(r.quadtree, settings), levels_(GL_TEXTURE_2D_ARRAY),
          programs_(r, {{GL_VERTEX_SHADER, "clipmaps.vert"}}, "clipmaps.frag")
    {
        const lod::ClipmapWindows& w = selector_.windows();
        texture_size_ = w.n() + 1;
        glTextureStorage3D(levels_.id(), 1, GL_RG16UI, texture_size_, texture_size_,
                           w.levelCount());
        // Integer texels: only nearest filtering makes the texture complete.
        glTextureParameteri(levels_.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTextureParameteri(levels_.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        for (int k = 0; k < lod::kFootprintKinds; ++k)
            meshes_[size_t(k)] =
                std::make_unique<FootprintMesh>(lod::makeFootprint(lod::FootprintKind(k), w.m()));
        fill_ = gpu::ShaderProgram({{GL_COMPUTE_SHADER, "clipmap_fill.comp"}});
        gpu::checkGlError("clipmaps: level textures");
    }

    lod::PatchSelector* selector() override { return &selector_; }

    bool buildInstances(const lod::Camera& camera, const RenderSettings& settings,
                        PatchInstances& out) override
    {
        writePending();
        out = PatchInstances{};
        records_.clear();
        kinds_.clear();
        const int finest = selector_.finestDrawn();
        if (finest < 0)
            return true; // the coarsest level waits for its patches: nothing to draw yet
        const lod::ClipmapWindows& w = selector_.windows();
        const lod::TerrainFrame& frame = quadtree_.frame();
        const CameraAnchor anchor = cameraAnchor(frame, camera.position());
        const lod::Frustum frustum(camera);
        const double k = settings.exaggeration;
        const int64_t W = frame.geometry().width() - 1, H = frame.geometry().height() - 1;
        // On a wrapping globe the columns have no border, but a level a turn wide would cover
        // the globe twice: such levels end at one meridian, drawn by the same level on both
        // sides (lod::ClipmapTurnCut).
        const glm::dvec2 c = selector_.centre();
        const lod::ClipmapTurnCut turn = selector_.turnCut(finest);
        const int coarsest = turn.coarsest;
        // The columns' ends: the terrain's border, the turn, or none on a wrapping globe whose
        // windows are all narrower than a turn.
        constexpr int64_t kNone = int64_t{1} << 60;
        const bool wraps = selector_.turn() > 0;
        const int64_t west = turn.cut ? turn.west : wraps ? -kNone : 0;
        const int64_t east = turn.cut ? turn.west + selector_.turn() : wraps ? kNone : W;
        std::vector<Entry> entries;
        for (int level = finest; level >= coarsest; --level) { // fine to coarse (§3.5.4)
            const lod::ClipmapLevel& l = w.level(level);
            const bool has_coarser = level > coarsest;
            for (const lod::FootprintPiece& piece :
                 lod::levelPieces(w.m(), level == finest, l.finer_x, l.finer_y, has_coarser)) {
                // The piece's finest-grid corners.
                const int64_t x0 = l.origin_x + piece.x * l.step,
                              y0 = l.origin_y + piece.y * l.step;
                const int64_t x1 = x0 + (piece.width - 1) * l.step;
                const int64_t y1 = y0 + (piece.height - 1) * l.step;
                if (y1 <= 0 || y0 >= H || x1 <= west || x0 >= east)
                    continue; // wholly off the terrain (or only touching its border line)
                float lo = 0.f, hi = 0.f;
                if (!visible(level, x0, y0, x1, y1, k, settings.cull ? &frustum : nullptr, lo, hi))
                    continue;
                GpuPatchInstance r{};
                r.origin[0] = int32_t(x0 - anchor.column);
                r.origin[1] = int32_t(y0 - anchor.row);
                r.step = int32_t(l.step);
                r.layer = level;
                r.level = std::max(l.pyramid_level, 0); // the archive level (legend colours)
                // No skirts; a wall under the terrain's clipped border hangs this deep.
                r.skirt_depth = float(k * double(hi - lo) + 1.0);
                // Cut on the east and south borders; dropped west and north of the terrain.
                // On the globe the turn's ends and a pole row lie on every level's grid
                // (lod::checkClipmapGlobe): the clip stage drops what lies beyond them
                // (u_drop_beyond) instead of cutting it.
                r.valid_extent[0] =
                    x1 > east ? float(double(east - x0) / double(l.step)) : kUnclipped;
                r.valid_extent[1] = y1 > H ? float(double(H - y0) / double(l.step)) : kUnclipped;
                r.valid_start[0] = x0 < west ? float((west - x0) / l.step) : 0.f;
                r.valid_start[1] = y0 < 0 ? float(-y0 / l.step) : 0.f;
                r.min_z = float(k * double(lo) - anchor.height);
                r.max_z = float(k * double(hi) - anchor.height);
                ClipmapPieceRecord pr{};
                const int64_t wx = l.origin_x / l.step, wy = l.origin_y / l.step;
                pr.texel[0] = wrapTexel(wx, texture_size_);
                pr.texel[1] = wrapTexel(wy, texture_size_);
                pr.coarse_layer = has_coarser ? level - 1 : -1;
                pr.coarse_texel[0] = wrapTexel(l.origin_x / (2 * l.step), texture_size_);
                pr.coarse_texel[1] = wrapTexel(l.origin_y / (2 * l.step), texture_size_);
                pr.viewer[0] = float((c.x - double(l.origin_x)) / double(l.step));
                pr.viewer[1] = float((c.y - double(l.origin_y)) / double(l.step));
                pr.local[0] = piece.x;
                pr.local[1] = piece.y;
                pr.kind = int32_t(piece.kind);
                const bool partial = x0 < west || y0 < 0 || x1 > east || y1 > H;
                entries.push_back({partial, piece.kind, r, pr,
                                   selector_.patchOf(level, wx + piece.x, wy + piece.y)});
            }
        }
        // Whole pieces first (the clipping draw takes the rest), by kind within a group so that
        // one draw covers a run of one footprint, finer levels first within a kind.
        std::stable_sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) {
            if (a.partial != b.partial)
                return !a.partial;
            return a.kind < b.kind;
        });
        for (const Entry& e : entries) {
            out.records.push_back(e.record);
            out.patches.push_back(e.patch);
            records_.push_back(e.piece);
            kinds_.push_back(e.kind);
            (e.partial ? out.partial : out.whole) += 1;
        }
        return true;
    }

    size_t beginDraw(const SchemeFrame&) override
    {
        return buffer_.upload(records_) + written_bytes_;
    }

    void addFrameStats(FrameStats& stats) const override
    {
        stats.levels = selector_.windows().levelCount();
        stats.level_shifts = selector_.shifts();
        stats.levels_drawn = selector_.finestDrawn() + 1;
        stats.levels_wanted = selector_.finestWanted() + 1;
        stats.samples_written = written_bytes_ / 4;
    }

    double meshDeviation(int) const override { return 0.0; }

    std::array<const gpu::ShaderProgram*, 2> programs(bool capture, bool fading,
                                                      const RenderSettings&) override
    {
        return programs_.get(capture, fading);
    }

    void setUniforms(const gpu::ShaderProgram& program, const SchemeFrame& frame) const override
    {
        const lod::ClipmapWindows& w = selector_.windows();
        const GLuint id = program.id();
        glProgramUniform1i(id, program.uniform("u_texture_size"), texture_size_);
        glProgramUniform1i(id, program.uniform("u_window"), w.n());
        // Pieces have up to n − 1 cells: clipped wherever their valid extent is a real one.
        glProgramUniform1f(id, program.uniform("u_unclipped_extent"), kUnclipped);
        // On the globe the cuts that end a level's turn, and the one at a pole on the last row,
        // are grid lines of every level (lod::ClipmapSelector): triangles beyond are dropped.
        const lod::TerrainFrame& f = quadtree_.frame();
        const bool south_pole = f.onEllipsoid() && f.poleRow(double(f.geometry().height() - 1));
        glProgramUniform2i(id, program.uniform("u_drop_beyond"), selector_.turn() > 0 ? 1 : 0,
                           south_pole ? 1 : 0);
        const double width = lod::transitionWidth(w.n());
        glProgramUniform2f(id, program.uniform("u_transition"), float((w.n() - 1) / 2 - width - 2),
                           float(width));
        // The fragment stage's per-level table.
        const CameraAnchor anchor = cameraAnchor(quadtree_.frame(), frame.camera.position());
        const int L = w.levelCount();
        const size_t count = static_cast<size_t>(L);
        std::vector<GLint> texel(2 * count), origin(2 * count), steps(count);
        std::vector<GLfloat> in_coarser(2 * count, 0.f);
        for (int k = 0; k < L; ++k) {
            const lod::ClipmapLevel& l = w.level(k);
            texel[size_t(2 * k)] = wrapTexel(l.origin_x / l.step, texture_size_);
            texel[size_t(2 * k + 1)] = wrapTexel(l.origin_y / l.step, texture_size_);
            origin[size_t(2 * k)] = GLint(l.origin_x - anchor.column);
            origin[size_t(2 * k + 1)] = GLint(l.origin_y - anchor.row);
            steps[size_t(k)] = GLint(l.step);
            if (k > 0) {
                const lod::ClipmapLevel& coarse = w.level(k - 1);
                in_coarser[size_t(2 * k)] = float((l.origin_x - coarse.origin_x) / coarse.step);
                in_coarser[size_t(2 * k + 1)] = float((l.origin_y - coarse.origin_y) / coarse.step);
            }
        }
        glProgramUniform2iv(id, program.uniform("u_level_texel"), L, texel.data());
        glProgramUniform2iv(id, program.uniform("u_level_origin"), L, origin.data());
        glProgramUniform1iv(id, program.uniform("u_level_step"), L, steps.data());
        glProgramUniform2fv(id, program.uniform("u_in_coarser"), L, in_coarser.data());
        glBindTextureUnit(11, levels_.id());
    }

    // Runs of one footprint within [first, first + count): one instanced draw each.
    void draw(const gpu::ShaderProgram& program, const SchemeFrame&, size_t first,
              size_t count) const override
    {
        buffer_.bind(3);
        for (size_t begin = first, end = first + count; begin < end;) {
            size_t run = begin + 1;
            while (run < end && kinds_[run] == kinds_[begin])
                ++run;
            glUniform1i(program.uniform("u_instance_offset"), GLint(begin));
            meshes_[size_t(kinds_[begin])]->draw(run - begin);
            begin = run;
        }
    }

    size_t maxTrianglesPerInstance(bool) const override
    {
        size_t most = 0;
        for (const auto& m : meshes_)
            most = std::max(most, m->triangles());
        return most;
    }

  private:
    struct Entry {
        bool partial;
        lod::FootprintKind kind;
        GpuPatchInstance record;
        ClipmapPieceRecord piece;
        PatchId patch;
    };

    // The writes whose patches are resident, into the level textures (coarse first).
    void writePending()
    {
        selector_.takeWrites([&](PatchId p) { return residency_.slotOf(p) >= 0; }, writes_);
        written_bytes_ = 0;
        if (writes_.empty())
            return;
        const PyramidGeometry& g = quadtree_.geometry();
        textures_.bind();
        glBindImageTexture(0, levels_.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RG16UI);
        fill_.use();
        const GLuint id = fill_.id();
        glProgramUniform1i(id, fill_.uniform("u_texture_size"), texture_size_);
        glProgramUniform1i(id, fill_.uniform("u_patch_cells"), g.cells());
        for (const lod::ClipmapWrite& wr : writes_) {
            const int archive_level = wr.patch.level;
            glProgramUniform4i(id, fill_.uniform("u_rect"), GLint(wr.rect.x0), GLint(wr.rect.y0),
                               GLint(wr.rect.x1), GLint(wr.rect.y1));
            glProgramUniform1i(id, fill_.uniform("u_layer"), wr.level);
            glProgramUniform1i(id, fill_.uniform("u_slot"), residency_.slotOf(wr.patch));
            glProgramUniform2i(id, fill_.uniform("u_patch_origin"), wr.patch.x * g.cells(),
                               wr.patch.y * g.cells());
            glProgramUniform1i(id, fill_.uniform("u_wrap_shift"), GLint(wr.wrap_shift));
            glProgramUniform1i(id, fill_.uniform("u_decimation"),
                               GLint(selector_.decimation(wr.level)));
            glProgramUniform2i(id, fill_.uniform("u_level_last"), g.levelWidth(archive_level) - 1,
                               g.levelHeight(archive_level) - 1);
            const int64_t w = wr.rect.x1 - wr.rect.x0, h = wr.rect.y1 - wr.rect.y0;
            glDispatchCompute(GLuint((w + 7) / 8), GLuint((h + 7) / 8), 1);
            written_bytes_ += size_t(w * h) * 4;
        }
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
        gpu::checkGlError("clipmaps: level writes");
    }

    // Whether the piece with finest corners (x0, y0)–(x1, y1) of `level` may be in view, and
    // its heights: those of the patches of the next coarser archive level under it (their
    // bounds hold this level's samples and the coarser ones the transition blends towards).
    bool visible(int level, int64_t x0, int64_t y0, int64_t x1, int64_t y1, double k,
                 const lod::Frustum* frustum, float& lo, float& hi) const
    {
        const PyramidGeometry& g = quadtree_.geometry();
        const int archive = std::max(selector_.windows().level(level).pyramid_level - 1, 0);
        const int64_t span = int64_t(g.cells()) * g.step(archive);
        const int py0 = int(std::clamp<int64_t>(y0 / span, 0, g.patchesY(archive) - 1));
        const int py1 = int(std::clamp<int64_t>((y1 - 1) / span, 0, g.patchesY(archive) - 1));
        bool seen = frustum == nullptr;
        lo = INFINITY;
        hi = -INFINITY;
        // The patches under columns [a, b) (on the terrain's own columns).
        auto under = [&](int64_t a, int64_t b) {
            const int px0 = int(std::clamp<int64_t>(a / span, 0, g.patchesX(archive) - 1));
            const int px1 = int(std::clamp<int64_t>((b - 1) / span, 0, g.patchesX(archive) - 1));
            for (int y = py0; y <= py1; ++y)
                for (int x = px0; x <= px1; ++x) {
                    const PatchId p{archive, x, y};
                    const lod::PatchBounds& bounds = quadtree_.bounds(p);
                    lo = std::min(lo, bounds.min_height);
                    hi = std::max(hi, bounds.max_height);
                    if (!seen)
                        seen = frustum->classify(quadtree_.frame().patchBox(
                                   p, k * double(bounds.min_height),
                                   k * double(bounds.max_height))) != lod::Visibility::Outside;
                }
        };
        if (const int64_t turn = selector_.turn(); turn > 0) {
            // Columns wrapped into the first turn: the piece may cross the seam (it spans
            // less than a turn, lod::ClipmapSelector).
            const int64_t a = x0 - lod::floorDiv(x0, turn) * turn, b = a + (x1 - x0);
            under(a, std::min(b, turn));
            if (b > turn)
                under(0, b - turn);
        } else {
            under(x0, x1);
        }
        return seen;
    }

    const lod::PatchQuadtree& quadtree_;
    PatchTextures& textures_;
    const lod::PatchResidency& residency_;
    lod::ClipmapSelector selector_;
    int texture_size_ = 0;
    gpu::GlTexture levels_;
    gpu::ShaderProgram fill_;
    std::array<std::unique_ptr<FootprintMesh>, lod::kFootprintKinds> meshes_;
    std::vector<lod::ClipmapWrite> writes_;
    size_t written_bytes_ = 0;
    std::vector<ClipmapPieceRecord> records_;
    std::vector<lod::FootprintKind> kinds_; // per record
    RecordBuffer<ClipmapPieceRecord> buffer_;
    SchemePrograms programs_;
};

constexpr const char* kN = "n";
constexpr const char* kLevels = "levels";

// The clipmap's settings from the scheme's options, refused by option name (also levels that
// cannot lie on the frame's globe).
lod::ClipmapSettings settingsFor(const archive::ArchiveReader& reader,
                                 const lod::TerrainFrame& frame, const SchemeOptions& own)
{
    lod::ClipmapSettings settings;
    settings.n = int(own.integer(kN));
    settings.levels = int(own.integer(kLevels));
    try {
        settings.validate();
        lod::checkClipmapGlobe(frame, settings.n,
                               lod::clipmapLevelCount(settings, reader.geometry()));
    } catch (const Error& e) {
        throw Error(reader.path() + ": --lod " + own.spec() + ": " + e.what());
    }
    return settings;
}

} // namespace

SchemeInfo clipmapsScheme()
{
    return {
        .name = "clipmaps",
        .description = "the clipmaps thesis's GPU geometry clipmaps: nested n×n level windows "
                       "about the viewer, toroidal updates, transition regions (no skirts, no "
                       "screen-space bound)",
        .options = {SchemeOption::integer(kN,
                                          "samples a side of every level window, 2^k - 1: "
                                          "63, 127, 255, 511 or 1023",
                                          lod::ClipmapSettings::kMinN, lod::ClipmapSettings::kMaxN,
                                          255),
                    SchemeOption::integer(kLevels,
                                          "L, the level windows (0: enough for the coarsest to "
                                          "span the terrain)",
                                          0, lod::ClipmapSettings::kMaxLevels, 0)},
        .needs =
            [](const archive::ArchiveReader& reader, const lod::TerrainFrame& frame,
               const RendererOptions&, const SchemeOptions& own) {
                const lod::ClipmapSettings s = settingsFor(reader, frame, own);
                SchemeNeeds needs;
                const double texels = double(s.n + 1) * double(s.n + 1);
                needs.fixed_bytes = texels * 4.0 * lod::clipmapLevelCount(s, reader.geometry());
                return needs;
            },
        .make = [](const SchemeResources& r) -> std::unique_ptr<TerrainScheme> {
            return std::make_unique<ClipmapsScheme>(
                r, settingsFor(r.reader, r.quadtree.frame(), r.own));
        },
        // Arrivals are not faded: a level window takes new samples as the fill writes them
        // (lod/clipmap.h), with no patch record to fade.
        .promises = {.screen_space_error = false,
                     .seams = SchemePromises::Seams::Stitching,
                     .pop_free = false,
                     .wrapping_globe = true,
                     .arrivals = SchemePromises::Arrivals::Replace},
    };
}

} // namespace ridge::render
