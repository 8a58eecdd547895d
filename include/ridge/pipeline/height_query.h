#pragma once
// Terrain heights without a GL context: the surface of any level of an archive at any point,
// decoded on demand (GL-free; `ridge query`).
//
// The surface of level l is what the pyramid stores and the renderers draw from: bilinear
// between the level's decoded samples inside the covering patch (patches share their border
// samples, so any patch touching a point gives the same height). At the finest level that is
// the exact finest surface: at every sample position the decoded height, within Err(P) =
// δ_L (codec bound + quantization) of the source; between samples, their bilinear blend. At a
// coarser level it is the surface a LOD scheme draws when it selects that level there, within
// Err(P) of every finest sample it covers. `drawnPatch` says which patch (so level) the LOD selection
// (lod::PatchQuadtree) draws at a point for a given camera and ε.
//
// Points: any PointSpace (terrain_georeference.h). A point is on the raster when its
// pixel/line lies in [0, width] x [0, height] (the pixels' area, as GDAL sees the raster);
// the surface ends at the outermost sample centres, so points in the outer half pixel read the
// border samples' surface there (clamped). Off-raster points are reported (on_raster false,
// height NaN), not thrown: a batch goes on.
//
// Not thread-safe (the decoded-patch cache): one HeightQuery per thread.
#include "ridge/lod/patch_quadtree.h"
#include "ridge/pipeline/terrain_georeference.h"
#include "ridge/stream/patch_loader.h"

#include <limits>
#include <memory>
#include <optional>
#include <string>

namespace ridge {

struct HeightSample {
    bool on_raster = false;
    // On the raster, but in a cell the archive keeps as nodata (docs/FORMAT.md, "Validity
    // mask"): no renderer draws it and it has no height (NaN), like a point off the raster.
    bool nodata = false;
    double height = std::numeric_limits<double>::quiet_NaN(); // metres, NaN off the raster
    glm::dvec2 local{0.0};    // the point in the terrain frame, metres
    glm::dvec2 pixel{0.0};    // and as GDAL pixel/line (sample (c, r) at (c + 0.5, r + 0.5))
    int level = 0;            // level whose surface was read
    PatchId patch;            // the covering patch that was read (on the raster only)
    double error_bound = 0.0; // Err(P) of that patch, metres: its surface vs the finest data
};

class HeightQuery {
  public:
    // Decoded patches kept (LRU); at least the pyramid depth is kept whatever is asked. 256
    // patches of 129² samples hold 8.5 MB.
    static constexpr size_t kDefaultCachePatches = 256;

    // Opens the archive (header, metadata and index; no patch yet). Throws ridge::Error for an
    // unreadable or invalid archive.
    explicit HeightQuery(const std::string& archive_path,
                         size_t cache_patches = kDefaultCachePatches);
    ~HeightQuery();
    HeightQuery(const HeightQuery&) = delete;
    HeightQuery& operator=(const HeightQuery&) = delete;

    const archive::ArchiveReader& reader() const { return *reader_; }
    const TerrainGeoreference& georeference() const { return georeference_; }
    int finestLevel() const { return reader_->geometry().finestLevel(); }

    // The surface of `level` (the finest when < 0) at `point` given in `space`. Throws
    // ridge::Error for a level beyond the finest, non-finite coordinates, a longitude/latitude
    // out of range, a space the archive lacks, or a corrupt patch.
    HeightSample sample(glm::dvec2 point, PointSpace space = PointSpace::Crs, int level = -1);

    // The patch the LOD selection draws at local point `local` for `camera` and `settings`
    // (lod::PatchQuadtree::select: its id, so its level, and Err_Scr), or nullopt when no
    // selected patch covers the point (off the raster, or culled by the view frustum).
    // sample(local, PointSpace::Local, drawn->id.level) is then the surface drawn there.
    // Throws ridge::Error for settings PatchQuadtree refuses.
    std::optional<lod::SelectedPatch> drawnPatch(const lod::Camera& camera,
                                                 const lod::SelectionSettings& settings,
                                                 glm::dvec2 local) const;

  private:
    std::unique_ptr<archive::ArchiveReader> reader_;
    TerrainGeoreference georeference_;
    lod::PatchQuadtree quadtree_;
    stream::PatchLoader loader_;
};

} // namespace ridge
