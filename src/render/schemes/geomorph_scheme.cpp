// Scheme "geomorph": GPU geomorphing with compact vertices (Ma, Sun & Song, "Accelerate
// terrain rendering using programmable graphics hardware", 2013), over ridge's patch
// quadtree. Every selected patch is its regular grid (one block of at most 128 cells); each
// vertex morphs between its own height and the parent level's surface (the target height
// field, lod::targetHeights) by the patch's factor t, chosen from ridge's screen-space errors
// so that ε holds at every morph state and a patch that changes level does not jump
// (lod::morphFactor says why). Skirts hang by Err(P) plus the largest morph displacement.
//
// The vertex layouts are the paper's (option layout=standard|float|compact): Standard morphs
// on the CPU and sends positions every frame; FloatMorph and Compact morph in geomorph.vert.
// Compact's normals index a hemisphere texture (option normals=orthographic|concentric).
// Option per-frame=on is the paper's regime (no display lists: every drawn patch's vertices
// sent every frame); otherwise they stay resident in a per-slot buffer.
#include "../scheme_programs.h"
#include "../terrain_scheme.h"

#include "ridge/core/error.h"
#include "ridge/lod/geomorph.h"
#include "ridge/lod/hemisphere_normals.h"
#include "ridge/lod/screen_space_error.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>

namespace ridge::render {
namespace {

using lod::GeomorphLayout;

// The options (SchemeInfo::options below), as the spec spells them.
constexpr const char* kLayout = "layout";
constexpr const char* kNormals = "normals";
constexpr const char* kPerFrame = "per-frame";

GeomorphLayout layoutOf(const SchemeOptions& own)
{
    const std::string& name = own.choice(kLayout);
    return name == "standard" ? GeomorphLayout::Standard
           : name == "float"  ? GeomorphLayout::FloatMorph
                              : GeomorphLayout::Compact;
}

lod::HemisphereMap normalMapOf(const SchemeOptions& own)
{
    return own.choice(kNormals) == "concentric" ? lod::HemisphereMap::Concentric
                                                : lod::HemisphereMap::Orthographic;
}
using lod::GeomorphShading;

// Vertices of one patch: its n² samples, then 4C foot copies of its border ring.
size_t patchVertices(int n)
{
    return size_t(n) * n + 4 * size_t(n - 1);
}

int vertexBytes(GeomorphLayout layout)
{
    return lod::geomorphVertexBytes(layout, GeomorphShading::Lit);
}

// What the stream workers derive from a patch's codes.
struct PreparedGeomorph final : stream::PatchProduct {
    std::vector<uint8_t> vertices; // patchVertices(n) in the layout (Standard: at t = 0)
    // Standard re-packs every frame at the patch's t from these.
    std::vector<uint16_t> codes;
    std::vector<double> targets;
    std::vector<float> normals;
    float max_morph_metres = 0.f; // largest |target − own height|
    size_t bytes() const override
    {
        return sizeof(*this) + vertices.size() + codes.size() * 2 + targets.size() * 8 +
               normals.size() * 4;
    }
};

// Appends the foot copies of the border ring after the n² sample vertices.
void appendFeet(std::vector<uint8_t>& vertices, int n, int stride)
{
    const int C = n - 1;
    vertices.resize(patchVertices(n) * size_t(stride));
    auto ring = [&](int k) {
        if (k < C)
            return k;
        if (k < 2 * C)
            return (k - C) * n + C;
        if (k < 3 * C)
            return C * n + (C - (k - 2 * C));
        return (C - (k - 3 * C)) * n;
    };
    for (int k = 0; k < 4 * C; ++k)
        std::memcpy(&vertices[(size_t(n) * n + size_t(k)) * size_t(stride)],
                    &vertices[size_t(ring(k)) * size_t(stride)], size_t(stride));
}

// The patch's own decimated samples stand for its parent in quadrant (0, 0): the target is
// the parent level's surface, which with decimation is made of the patch's even samples.
// (A Neville-filtered parent differs from them by the filter; that difference shows as a
// pop when the level switches — the popping metric measures it.)
std::vector<double> targetsFromEvenSamples(const std::vector<uint16_t>& codes, int n)
{
    const int m = (n - 1) / 2;
    std::vector<uint16_t> parent(size_t(n) * n, 0);
    for (int j = 0; j <= m; ++j)
        for (int i = 0; i <= m; ++i)
            parent[size_t(j) * n + i] = codes[size_t(2 * j) * n + 2 * i];
    std::vector<double> targets(codes.size());
    lod::targetHeights(parent.data(), n, 0, 0, targets.data());
    return targets;
}

struct GeomorphSettings {
    GeomorphLayout layout;
    lod::HemisphereMap map;
    int n;
    double scale, offset; // HeightQuantization
    double spacing_x, spacing_y;
    int finest_level;
};

lod::GeomorphFrame patchFrame(const GeomorphSettings& s, int level)
{
    // Heights relative to the archive's offset (the shader adds offset − camera z), so that
    // floats keep their precision for any datum.
    const double step = std::ldexp(1.0, s.finest_level - level);
    return {s.scale, 0.0, step * s.spacing_x, step * s.spacing_y};
}

std::shared_ptr<const stream::PatchProduct> prepareGeomorph(const GeomorphSettings& s, PatchId p,
                                                            const uint16_t* codes)
{
    auto out = std::make_shared<PreparedGeomorph>();
    const int n = s.n;
    out->codes.assign(codes, codes + size_t(n) * n);
    out->targets = targetsFromEvenSamples(out->codes, n);
    const lod::GeomorphFrame frame = patchFrame(s, p.level);
    out->normals.resize(size_t(3) * n * n);
    lod::patchNormals(codes, n, frame, out->normals.data());
    double worst = 0.0;
    for (size_t i = 0; i < out->codes.size(); ++i)
        worst = std::max(worst, std::abs(out->targets[i] - double(out->codes[i])));
    out->max_morph_metres = float(worst * s.scale);
    const int stride = vertexBytes(s.layout);
    out->vertices.resize(lod::geomorphVertexCount(n) * size_t(stride));
    const lod::GeomorphPatchData data{n, out->codes.data(), out->targets.data(),
                                      out->normals.data()};
    switch (s.layout) {
    case GeomorphLayout::Standard:
        lod::packStandard(data, frame, 0.0, GeomorphShading::Lit, out->vertices.data());
        break;
    case GeomorphLayout::FloatMorph:
        lod::packFloatMorph(data, frame, GeomorphShading::Lit, out->vertices.data());
        break;
    case GeomorphLayout::Compact:
        lod::packCompact(data, s.map, GeomorphShading::Lit, out->vertices.data());
        break;
    }
    appendFeet(out->vertices, n, stride);
    if (s.layout != GeomorphLayout::Standard) { // only Standard re-packs on the CPU
        out->codes = {};
        out->targets = {};
        out->normals = {};
    }
    return out;
}

GeomorphSettings settingsOf(const archive::ArchiveReader& reader, const SchemeOptions& own)
{
    return {layoutOf(own),
            normalMapOf(own),
            reader.geometry().patchSize(),
            reader.quantization().scale,
            reader.quantization().offset,
            reader.header().spacing_x,
            reader.header().spacing_y,
            reader.geometry().finestLevel()};
}

class GeomorphScheme final : public TerrainScheme {
  public:
    explicit GeomorphScheme(const SchemeResources& r)
        : quadtree_(r.quadtree), settings_(settingsOf(r.reader, r.own)),
          per_frame_(r.own.flag(kPerFrame)), product_(r.product),
          stride_(vertexBytes(settings_.layout)), vertices_per_patch_(patchVertices(settings_.n)),
          slots_(size_t(r.slots)),
          // Its vertices carry their normals (terrain.frag's surfaceNormal).
          programs_(r, {{GL_VERTEX_SHADER, "geomorph.vert"}},
                    std::vector<std::vector<std::string>>{{"RIDGE_VERTEX_NORMALS 1"}})
    {
        const int n = settings_.n;
        if (n - 1 > lod::kGeomorphMaxBlockCells)
            throw Error(r.reader.path() + ": geomorph draws patches of at most " +
                        std::to_string(lod::kGeomorphMaxBlockCells + 1) +
                        " samples (one block: in-block coordinates are bytes); this archive's "
                        "have " +
                        std::to_string(n));
        if (settings_.layout == GeomorphLayout::Compact)
            target_rounding_ = 0.5 * settings_.scale;
        buildIndices(n);
        glNamedBufferStorage(vertices_.id(),
                             GLsizeiptr(size_t(r.slots) * vertices_per_patch_ * size_t(stride_)),
                             nullptr, GL_DYNAMIC_STORAGE_BIT);
        setUpVertexArray();
        const std::vector<uint8_t> texels = lod::buildHemisphereNormalTexture(settings_.map);
        glTextureStorage2D(hemisphere_.id(), 1, GL_RGBA8, 256, 256);
        glTextureSubImage2D(hemisphere_.id(), 0, 0, 0, 256, 256, GL_RGBA, GL_UNSIGNED_BYTE,
                            texels.data());
        glTextureParameteri(hemisphere_.id(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glTextureParameteri(hemisphere_.id(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glTextureParameteri(hemisphere_.id(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glTextureParameteri(hemisphere_.id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
        gpu::checkGlError("geomorph scheme: buffers");
    }

    size_t upload(const stream::DecodedPatch& patch, int slot) override
    {
        const auto& g = static_cast<const PreparedGeomorph&>(*patch.prepared.at(size_t(product_)));
        slots_[size_t(slot)] =
            std::static_pointer_cast<const PreparedGeomorph>(patch.prepared[size_t(product_)]);
        if (per_frame_ || settings_.layout == GeomorphLayout::Standard)
            return 0; // sent with every frame that draws it
        glNamedBufferSubData(vertices_.id(), slotOffset(slot), GLsizeiptr(g.vertices.size()),
                             g.vertices.data());
        return g.vertices.size();
    }
    size_t plannedUploadBytes(const stream::DecodedPatch&) const override
    {
        return per_frame_ ? 0 : vertices_per_patch_ * size_t(stride_);
    }

    // The morphed surface lies between the patch's own samples and its target.
    double meshDeviation(int slot) const override
    {
        const auto& g = slots_[size_t(slot)];
        return g ? double(g->max_morph_metres) : 0.0;
    }

    // t per patch from the LOD camera: the largest morph towards the parent that keeps
    // (1 − t)·Err_Scr(P) + t·Err_Scr(parent) <= ε, both projected over the patch's box.
    void completeInstances(const lod::Camera& lod_camera, const RenderSettings& settings,
                           PatchInstances& instances) const override
    {
        // In the exaggerated space (RenderSettings::exaggeration), as the selection measures.
        const double gamma = lod::screenSpaceErrorFactor(lod_camera) * settings.exaggeration;
        for (size_t k = 0; k < instances.patches.size(); ++k) {
            const PatchId p = instances.patches[k];
            if (p.level == 0) {
                instances.records[k].morph = 0.f;
                continue;
            }
            const lod::Box box = quadtree_.box(p, settings.exaggeration);
            const double rho = lod::visibleDepthBound(
                lod_camera, box, lod::distanceToBox(lod_camera.position(), box),
                settings.side_on_bound); // the selection's own bound
            // The errors the selection switches levels by (PatchQuadtree::select): on a globe
            // Err(P) plus the sagitta of the level's straight cells, so that t is 1 where the
            // parent would be selected and 0 where the children would.
            const lod::TerrainFrame& frame = quadtree_.frame();
            auto sag = [&](PatchId q) {
                return frame.chordSag(double(quadtree_.geometry().step(q.level))) /
                       settings.exaggeration;
            };
            const double own =
                lod::screen_space_error(gamma, quadtree_.bounds(p).err + sag(p), rho);
            // The compact layout's target codes are up to ½ code off the parent's surface.
            const double parent_err =
                quadtree_.bounds(p.parent()).err + target_rounding_ + sag(p.parent());
            const double parent = lod::screen_space_error(gamma, parent_err, rho);
            instances.records[k].morph = float(lod::morphFactor(own, parent, settings.epsilon_px));
        }
    }

    // The paper's regime and the CPU morph: this frame's vertices of every drawn patch.
    size_t beginDraw(const SchemeFrame& frame) override
    {
        const bool standard = settings_.layout == GeomorphLayout::Standard;
        if (!per_frame_ && !standard)
            return 0;
        size_t bytes = 0;
        for (const GpuPatchInstance& r : frame.instances.records) {
            const auto& g = slots_[size_t(r.layer)];
            if (!g)
                continue;
            const uint8_t* data = g->vertices.data();
            if (standard) {
                scratch_.resize(g->vertices.size());
                const lod::GeomorphPatchData patch{settings_.n, g->codes.data(), g->targets.data(),
                                                   g->normals.data()};
                lod::packStandard(patch, patchFrame(settings_, r.level), double(r.morph),
                                  GeomorphShading::Lit, scratch_.data());
                appendFeet(scratch_, settings_.n, stride_);
                data = scratch_.data();
            }
            glNamedBufferSubData(vertices_.id(), slotOffset(r.layer),
                                 GLsizeiptr(g->vertices.size()), data);
            bytes += g->vertices.size();
        }
        return bytes;
    }

    std::array<const gpu::ShaderProgram*, 2> programs(bool capture, bool fading,
                                                      const RenderSettings&) override
    {
        return programs_.get(capture, fading);
    }

    void setUniforms(const gpu::ShaderProgram& program, const SchemeFrame& frame) const override
    {
        const GLuint id = program.id();
        glProgramUniform1i(id, program.uniform("u_layout"), int(settings_.layout));
        glProgramUniform1i(id, program.uniform("u_hemisphere_map"), int(settings_.map));
        // Compact codes become drawn metres relative to the reference height directly:
        // k·offset − camera z on a plane (TerrainFrame::referenceHeight).
        const double k = frame.settings.exaggeration;
        glProgramUniform1f(id, program.uniform("u_geomorph_height_scale"),
                           float(k * settings_.scale));
        glProgramUniform1f(id, program.uniform("u_geomorph_height_offset"),
                           float(k * settings_.offset -
                                 quadtree_.frame().referenceHeight(frame.camera.position())));
        glBindTextureUnit(3, hemisphere_.id());
    }

    void draw(const gpu::ShaderProgram& program, const SchemeFrame& frame, size_t first,
              size_t count) const override
    {
        const GLint u_instance = program.uniform("u_instance");
        const GLint u_base = program.uniform("u_base_vertex");
        const GLint u_block = program.uniform("u_geomorph_block");
        const GLsizei indices = frame.settings.skirts ? all_ : surface_;
        glBindVertexArray(vao_.id());
        for (size_t i = first; i < first + count; ++i) {
            const int slot = frame.instances.records[i].layer;
            const GLint base = GLint(size_t(slot) * vertices_per_patch_);
            glUniform1i(u_instance, GLint(i));
            glUniform1i(u_base, base);
            // The paper's block identifier, once per block (one block per patch here).
            glUniform4i(u_block, 0, 0, GLint(i), settings_.n - 1);
            glDrawElementsBaseVertex(GL_TRIANGLES, indices, GL_UNSIGNED_SHORT, nullptr, base);
        }
    }

    size_t maxTrianglesPerInstance(bool skirts) const override
    {
        return size_t(skirts ? all_ : surface_) / 3;
    }

  private:
    GLintptr slotOffset(int slot) const
    {
        return GLintptr(size_t(slot) * vertices_per_patch_ * size_t(stride_));
    }

    // The block's cells (lod::buildGeomorphBlockIndices: the b–c diagonal every level shares,
    // so that a fully morphed patch is exactly its parent's surface), then the skirt: a quad
    // under each border cell between ring sample k and its foot n² + k.
    void buildIndices(int n)
    {
        const int C = n - 1;
        std::vector<uint16_t> indices(lod::geomorphBlockIndexCount(C));
        lod::buildGeomorphBlockIndices(C, indices.data());
        surface_ = GLsizei(indices.size());
        auto ring = [&](int k) -> uint16_t {
            if (k < C)
                return uint16_t(k);
            if (k < 2 * C)
                return uint16_t((k - C) * n + C);
            if (k < 3 * C)
                return uint16_t(C * n + (C - (k - 2 * C)));
            return uint16_t((C - (k - 3 * C)) * n);
        };
        const int R = 4 * C;
        for (int k = 0; k < R; ++k) {
            const uint16_t t0 = ring(k), t1 = ring((k + 1) % R);
            const uint16_t f0 = uint16_t(n * n + k), f1 = uint16_t(n * n + (k + 1) % R);
            indices.insert(indices.end(), {f0, t0, t1, f0, t1, f1});
        }
        all_ = GLsizei(indices.size());
        glNamedBufferStorage(indices_.id(), GLsizeiptr(indices.size() * sizeof(uint16_t)),
                             indices.data(), 0);
    }

    void setUpVertexArray()
    {
        const GLuint vao = vao_.id();
        glVertexArrayVertexBuffer(vao, 0, vertices_.id(), 0, stride_);
        glVertexArrayElementBuffer(vao, indices_.id());
        auto attribute = [&](GLuint location, GLint size, GLenum type, GLuint offset,
                             bool integer) {
            glEnableVertexArrayAttrib(vao, location);
            if (integer)
                glVertexArrayAttribIFormat(vao, location, size, type, offset);
            else
                glVertexArrayAttribFormat(vao, location, size, type, GL_FALSE, offset);
            glVertexArrayAttribBinding(vao, location, 0);
        };
        switch (settings_.layout) {
        case GeomorphLayout::Standard:
            attribute(0, 3, GL_FLOAT, offsetof(lod::StandardVertex, x), false);
            attribute(2, 3, GL_FLOAT, offsetof(lod::StandardVertex, nx), false);
            break;
        case GeomorphLayout::FloatMorph:
            attribute(0, 3, GL_FLOAT, offsetof(lod::FloatMorphVertex, x), false);
            attribute(1, 1, GL_FLOAT, offsetof(lod::FloatMorphVertex, target_z), false);
            attribute(2, 3, GL_FLOAT, offsetof(lod::FloatMorphVertex, nx), false);
            break;
        case GeomorphLayout::Compact:
            attribute(3, 2, GL_UNSIGNED_BYTE, offsetof(lod::CompactVertex, bx), true);
            attribute(4, 2, GL_UNSIGNED_SHORT, offsetof(lod::CompactVertex, height), true);
            attribute(5, 2, GL_UNSIGNED_BYTE, offsetof(lod::CompactVertex, normal_u), false);
            break;
        }
    }

    const lod::PatchQuadtree& quadtree_;
    GeomorphSettings settings_;
    bool per_frame_;
    int product_;
    int stride_;
    size_t vertices_per_patch_;
    double target_rounding_ = 0.0; // metres a target may be off the parent's surface
    std::vector<std::shared_ptr<const PreparedGeomorph>> slots_; // the CPU copy per slot
    std::vector<uint8_t> scratch_;                               // Standard's per-frame pack
    gpu::GlBuffer vertices_, indices_;
    gpu::GlVertexArray vao_;
    gpu::GlTexture hemisphere_{GL_TEXTURE_2D};
    GLsizei surface_ = 0, all_ = 0;
    SchemePrograms programs_;
};

SchemeNeeds geomorphNeeds(const archive::ArchiveReader& reader, const lod::TerrainFrame&,
                          const RendererOptions&, const SchemeOptions& own)
{
    SchemeNeeds needs;
    needs.codes_on_cpu = true; // vertex arrays are built from codes
    const int n = reader.geometry().patchSize();
    needs.slot_bytes = double(patchVertices(n)) * vertexBytes(layoutOf(own));
    const GeomorphSettings s = settingsOf(reader, own);
    if (n - 1 <= lod::kGeomorphMaxBlockCells)
        needs.preparation = [s](PatchId p, const uint16_t* codes) {
            return prepareGeomorph(s, p, codes);
        };
    return needs;
}

} // namespace

SchemeInfo geomorphScheme()
{
    return {
        .name = "geomorph",
        .description = "GPU geomorphing with compact vertices: every patch morphs towards its "
                       "parent's surface",
        .options = {SchemeOption::choice(
                        kLayout,
                        "the paper's vertex layout: standard (CPU morph, positions "
                        "sent every frame), float (GPU morph, float position, target "
                        "and normal) or compact (block coordinates, 16-bit codes, "
                        "2-byte hemisphere normal index)",
                        {"standard", "float", "compact"}, "compact"),
                    SchemeOption::choice(kNormals,
                                         "compact's hemisphere normal texture: orthographic or "
                                         "concentric (Shirley and Chiu's map)",
                                         {"orthographic", "concentric"}, "orthographic"),
                    SchemeOption::flag(kPerFrame,
                                       "send every drawn patch's vertices every frame (the paper's "
                                       "regime, no resident buffers)",
                                       false)},
        .needs = geomorphNeeds,
        .make = [](const SchemeResources& r) -> std::unique_ptr<TerrainScheme> {
            return std::make_unique<GeomorphScheme>(r);
        },
    };
}

} // namespace ridge::render
