#pragma once
// One LOD scheme of the terrain renderer (internal to ridge_render): how selected patches of
// the patch quadtree become triangles. Every scheme draws over the same shared pieces, which
// the renderer owns and lends (SchemeResources): the archive and its patch quadtree, the
// texture arrays of resident patches and their slots, the instance records, frame uniforms
// and shading, sky, transform-feedback capture and the timer and primitive queries. A scheme
// adds only what is its own: how it adjusts the coarse selection, what it derives from a
// patch's codes on the stream workers, what it uploads per slot, its programs and its draw.
//
// A scheme is one file under src/render/schemes/ plus one line in scheme_registry.cpp, with
// its own options declared there (SchemeInfo::options); nothing else in ridge names a scheme
// (CLI, bench, viewer and tests take the registry's names; scripts/check-layering.sh refuses
// a scheme's name as a string literal elsewhere, except in its own tests,
// tests/render/schemes/<module>_test.cpp). Schemes are CDLOD-style modules: read one alone to
// see the whole of its algorithm.
#include "patch_instances.h"
#include "patch_textures.h"

#include "ridge/archive/archive_reader.h"
#include "ridge/gpu/shader_program.h"
#include "ridge/lod/patch_quadtree.h"
#include "ridge/lod/patch_residency.h"
#include "ridge/lod/patch_selector.h"
#include "ridge/render/scheme_options.h"
#include "ridge/render/terrain_renderer.h"
#include "ridge/stream/patch_loader.h"

#include <array>
#include <memory>
#include <string>
#include <vector>

namespace ridge::render {

// What a scheme needs decided before the renderer allocates anything, from the archive, the
// terrain frame the renderer draws it in, the renderer's options and the scheme's own options
// alone.
//
// They also decide when the scheme's object is constructed. A scheme that keeps per-slot data
// (slot_bytes > 0 or a preparation) is constructed with the renderer, so that upload() sees
// every patch that becomes resident. Any other is constructed on the first frame that draws it
// (a renderer built for several schemes allocates only those it draws); it sees only the uploads
// from then on, so it must keep nothing per slot: its upload() and plannedUploadBytes() send
// and store nothing.
struct SchemeNeeds {
    // Codes on the CPU for every patch (no GPU reconstruction of progressive residuals):
    // schemes that build meshes or vertex arrays from heights.
    bool codes_on_cpu = false;
    // Texture or buffer memory per resident slot beyond the shared texture arrays, bytes at
    // most: the VRAM budget counts it.
    double slot_bytes = 0.0;
    // Texture or buffer memory the scheme holds whatever is resident (clipmaps' level
    // windows), bytes: the VRAM budget takes it before sizing the slots.
    double fixed_bytes = 0.0;
    // What the scheme derives from a patch's codes on the stream workers (null: nothing).
    // Its product reaches upload() as DecodedPatch::prepared[SchemeResources::product].
    stream::PatchPreparation preparation;
};

// The renderer's shared pieces, lent to a scheme for the renderer's lifetime.
struct SchemeResources {
    const archive::ArchiveReader& reader;
    const lod::PatchQuadtree& quadtree;
    const RendererOptions& options;
    const SchemeOptions& own; // this scheme's options (SchemeInfo::options, as its spec set them)
    PatchTextures& textures;
    const lod::PatchResidency& residency;
    int slots = 0;
    // Index of this scheme's product in DecodedPatch::prepared; −1 when it prepares none.
    int product = -1;
};

// One frame's inputs to a scheme's draw, after selection, residency and instance records.
struct SchemeFrame {
    const lod::Camera& camera;      // the camera drawn from
    const lod::Camera& lod_camera;  // the camera LOD decisions are made for (usually the same)
    const RenderSettings& settings; // with the ε actually met
    const PatchInstances& instances;
};

class TerrainScheme {
  public:
    virtual ~TerrainScheme() = default;

    // Coarse LOD: how this scheme walks the patch quadtree (ε, the mesh's error scale).
    virtual void adjustSelection(const RenderSettings& /*settings*/,
                                 lod::SelectionSettings& /*selection*/) const
    {
    }
    // A scheme that owns its selection returns its selector (plain C++, lod::PatchSelector):
    // the renderer selects with it instead of the quadtree walk, the streaming planner ranks
    // its requests, prefetches and keeps resident what its cover draws. Null (the default):
    // the screen-space-error walk, with adjustSelection, and the resident cover.
    virtual lod::PatchSelector* selector() { return nullptr; }
    // The instance records of what the selector's last cover draws, for a scheme whose drawn
    // pieces are not one per patch (rings: tiles that share their level's patch). False (the
    // default): one record per drawn patch, skirts by Err(P) and meshDeviation.
    virtual bool buildInstances(const lod::Camera& /*camera*/, const RenderSettings& /*settings*/,
                                PatchInstances& /*out*/)
    {
        return false;
    }
    // Makes the scheme's own per-slot data for `patch` resident in `slot` (after the shared
    // textures: heights, normals, λ). Returns the bytes sent.
    virtual size_t upload(const stream::DecodedPatch& /*patch*/, int /*slot*/) { return 0; }
    // What upload() sends for `patch` at most (the per-frame upload budget plans with it).
    virtual size_t plannedUploadBytes(const stream::DecodedPatch& /*patch*/) const { return 0; }
    // Metres the drawn mesh of the patch in `slot` may lie beyond Err(P) from the patch's
    // own samples (what the skirts must hang by besides Err(P)).
    virtual double meshDeviation(int slot) const = 0;
    // Fills what the scheme keeps in the instance records (GpuPatchInstance::morph) before
    // they are uploaded; `lod_camera` is the camera LOD is decided for.
    virtual void completeInstances(const lod::Camera& /*lod_camera*/,
                                   const RenderSettings& /*settings*/,
                                   PatchInstances& /*instances*/) const
    {
    }
    // Per-frame work before the draws (vertex streams sent every frame, ...). Returns bytes
    // sent to the GPU.
    virtual size_t beginDraw(const SchemeFrame& /*frame*/) { return 0; }
    // The programs for whole patches and for patches clipped at the valid extent; `capture`:
    // the transform-feedback variants (no fragment stage); `fading`: for patches that fade in
    // (PatchInstances' fading groups); `settings`: the frame's, for a scheme that compiles a
    // choice in (SchemePrograms variants). Compiled on first use.
    virtual std::array<const gpu::ShaderProgram*, 2> programs(bool capture, bool fading,
                                                              const RenderSettings& settings) = 0;
    // Sets the scheme's own uniforms of `program` (the shared ones are set already).
    virtual void setUniforms(const gpu::ShaderProgram& /*program*/,
                             const SchemeFrame& /*frame*/) const
    {
    }
    // Draws instances [first, first + count) of frame.instances with `program`, in use.
    virtual void draw(const gpu::ShaderProgram& program, const SchemeFrame& frame, size_t first,
                      size_t count) const = 0;
    // Adds what the scheme alone knows about the frame it drew last (FrameStats' level
    // windows).
    virtual void addFrameStats(FrameStats& /*stats*/) const {}
    // Triangles one instance may produce at most (transform-feedback capture sizes with it).
    virtual size_t maxTrianglesPerInstance(bool skirts) const = 0;
};

// A module's registration, written with designated initializers
// ({.name = ..., .description = ..., .options = ..., .needs = ..., .make = ...}) so that
// fields added later need no change to the modules that do not use them.
struct SchemeInfo {
    const char* name;        // as the CLI, the benchmark and the viewer spell it
    const char* description; // one line for --help and reports
    // The scheme's own options, as its spec sets them ("NAME,KEY=VALUE,..."; see
    // ridge/render/scheme_options.h); --help lists them from here.
    std::vector<SchemeOption> options;
    SchemeNeeds (*needs)(const archive::ArchiveReader& reader, const lod::TerrainFrame& frame,
                         const RendererOptions& options, const SchemeOptions& own);
    std::unique_ptr<TerrainScheme> (*make)(const SchemeResources& resources);
    SchemePromises promises = {}; // what the conformance suite holds it to
};

// Every scheme, in registration order (scheme_registry.cpp).
const std::vector<SchemeInfo>& schemeRegistry();
// The registered scheme called `name`; throws ridge::Error listing the names otherwise.
const SchemeInfo& schemeNamed(const std::string& name);

} // namespace ridge::render
