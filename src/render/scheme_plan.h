#pragma once
// The LOD schemes one renderer draws (internal to ridge_render): which ones RendererOptions
// asks for and what they need, decided before anything is allocated (planSchemes: slots,
// stream preparations, codes on the CPU), and their TerrainScheme objects over the renderer's
// shared pieces (Schemes), each constructed when a frame first draws it unless it keeps
// per-slot data (terrain_scheme.h, SchemeNeeds, says why).
#include "ridge/archive/archive_reader.h"
#include "ridge/lod/terrain_frame.h"
#include "ridge/render/scheme_options.h"
#include "ridge/render/terrain_renderer.h"
#include "ridge/stream/patch_loader.h"

#include <memory>
#include <string>
#include <vector>

namespace ridge::render {

struct SchemeInfo;
struct SchemeResources;
class TerrainScheme;

// The schemes `options` asks for (all registered ones that need no CPU codes with their
// default options when empty, less any whose fixed memory would take over a quarter of the
// texture budget), with their own options and what they need.
struct SchemePlan {
    std::vector<const SchemeInfo*> infos;
    std::vector<std::string> names; // per scheme
    std::vector<SchemeOptions> own; // per scheme: its options, from its spec
    std::vector<int> product;       // per scheme: index into preparations, or −1
    std::vector<bool> eager;        // per scheme: keeps per-slot data (constructed at once)
    double slot_bytes = 0.0;        // per slot, all schemes together
    double fixed_bytes = 0.0;       // beside the slots, all schemes together
    bool codes_on_cpu = false;
    std::vector<stream::PatchPreparation> preparations;
};

// `frame`: the one the renderer draws `reader` in (lod::terrainFrameOf with options.frame,
// formed once: on a projected grid it samples PROJ into a lattice).
SchemePlan planSchemes(const archive::ArchiveReader& reader, const lod::TerrainFrame& frame,
                       const RendererOptions& options);

// The planned schemes' objects: the eager ones from construction on, the others from the first
// frame that draws them.
class Schemes {
  public:
    // `plan` and what `shared` lends (its `own` and product are each scheme's) must outlive
    // this.
    Schemes(const SchemePlan& plan, const SchemeResources& shared);
    ~Schemes();
    Schemes(const Schemes&) = delete;
    Schemes& operator=(const Schemes&) = delete;

    // The scheme called `name`, constructed on first use; throws ridge::Error when this
    // renderer was not built for it.
    TerrainScheme& get(const std::string& name);
    // Makes `patch` resident in `slot` for every constructed scheme (TerrainScheme::upload,
    // after the shared textures). Returns the bytes sent.
    size_t upload(const stream::DecodedPatch& patch, int slot);
    // What upload() sends for `patch` at most.
    size_t plannedUploadBytes(const stream::DecodedPatch& patch) const;

  private:
    const SchemePlan& plan_;
    std::unique_ptr<const SchemeResources> shared_;
    std::vector<std::unique_ptr<TerrainScheme>> schemes_; // plan order; null until constructed
};

} // namespace ridge::render
