#pragma once
// Terrain heights without a GL context: the surface of any level of an archive at any point,
// decoded on demand (GL-free; `ridge query`, ridge::Terrain).
//
// The surface of level l is what the pyramid stores and the renderers draw from: bilinear
// between the level's decoded samples inside the covering patch (patches share their border
// samples, so any patch touching a point gives the same height). At the finest level that is
// the exact finest surface: at every sample position the decoded height, within Err(P) =
// δ_L (codec bound + quantization) of the source; between samples, their bilinear blend. At a
// coarser level it is the surface a LOD scheme draws when it selects that level there, within
// Err(P) of every finest sample it covers. `drawnPatch` says which patch (so level) the LOD
// selection (lod::PatchQuadtree) draws at a point for a given camera and ε.
//
// QueryResampling::Nearest answers the level's sample nearest to the point instead: at the finest
// level the sample whose GDAL pixel holds it (pixel ⌊P⌋, line ⌊L⌋), as gdallocationinfo does.
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
#include "ridge/stream/lru_cache.h"
#include "ridge/stream/patch_loader.h"

#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace ridge {

// How a point between a level's samples is answered.
enum class QueryResampling : uint8_t {
    // The level's surface: bilinear between the four samples around the point (what the
    // renderers draw there, up to their triangulation).
    Bilinear,
    // The level's sample nearest to the point. At the finest level: the sample whose GDAL
    // pixel holds the point, pixel ⌊P⌋ and line ⌊L⌋ (clamped to the raster), which is
    // gdallocationinfo's answer; nodata when that sample is (not when a cell around it is).
    Nearest,
};
// "bilinear", "nearest".
std::string_view resamplingName(QueryResampling resampling);
// The inverse of resamplingName; nullopt for any other text.
std::optional<QueryResampling> parseResampling(std::string_view name);

struct HeightSample {
    bool on_raster = false;
    // On the raster, but where the archive keeps nodata (docs/FORMAT.md, "Validity mask"):
    // bilinear, a cell no renderer draws; nearest, a sample that is not data. No height (NaN).
    bool nodata = false;
    // sampleBatch only: the point could not be converted (non-finite, a longitude/latitude
    // out of range, PROJ refused it); sample() of the same point throws the reason.
    bool invalid_point = false;
    double height = std::numeric_limits<double>::quiet_NaN(); // metres, NaN off the raster
    // On kept nodata only: the value the archive stores there (filled from the valid samples
    // around at build, so the pyramid and codecs run on; not terrain), read as `height`
    // would be. A function of the position alone, so two readers of one point agree (web
    // tiles fill nodata with it). NaN elsewhere.
    double nodata_fill = std::numeric_limits<double>::quiet_NaN();
    glm::dvec2 local{0.0};    // the point in the terrain frame, metres
    glm::dvec2 pixel{0.0};    // and as GDAL pixel/line (sample (c, r) at (c + 0.5, r + 0.5))
    int level = 0;            // level whose surface was read
    PatchId patch;            // the covering patch that was read (on the raster only)
    double error_bound = 0.0; // Err(P) of that patch, metres: its samples vs the source
    // The archive's sample flags there (docs/FORMAT.md, "Sample flags"), with a height only.
    // Nearest: the sample's own. Bilinear: water where the blend of the four samples' water
    // bits is at least 1/2 (the renderers' rule, so a query agrees with the picture); filled
    // where any sample that weighs in was invented by void filling. Archives before format 4
    // store no flags: water is the height rule of then (<= 0 m) and nothing is filled.
    bool water = false;
    bool filled = false;
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
    // Patches decoded and cache hits so far (the batch's one decode a patch, in tests).
    const stream::LoaderStats& loaderStats() const { return loader_.stats(); }

    // The surface of `level` (the finest when < 0) at `point` given in `space`. Throws
    // ridge::Error for a level beyond the finest, non-finite coordinates, a longitude/latitude
    // out of range, a space the archive lacks, or a corrupt patch.
    HeightSample sample(glm::dvec2 point, PointSpace space = PointSpace::Crs, int level = -1,
                        QueryResampling resampling = QueryResampling::Bilinear);

    // sample() of every point: out[k] answers points[k]. The points are placed first; then,
    // when the patches they touch and the ancestors their decodes load fit in the cache, read
    // in input order (an LRU keeps that working set), else patch by patch (a counting sort
    // by the patch they fall in): either way each patch the points fall in is decoded at
    // most once a call whatever the cache size, so random points over a large archive cost
    // one decode per patch touched, not one per point (in patch order with a cache smaller
    // than an ancestor chain's reuse, a progressive patch's ancestors may be decoded again).
    // A point that cannot be
    // converted gets invalid_point (the batch goes on; sample() gives the reason). Throws
    // ridge::Error when out.size() differs from points.size(), for a level beyond the finest,
    // a space the archive lacks (CRS without a geotransform, longitude/latitude without a
    // CRS), or a corrupt patch. Memory: 28 bytes a point besides `out`.
    void sampleBatch(std::span<const glm::dvec2> points, PointSpace space, int level,
                     QueryResampling resampling, std::span<HeightSample> out);
    // sampleBatch's work, each answer handed to `emit(k, sample)` for points[k] instead of
    // stored: once a point, in no particular order (off-raster and invalid points first,
    // then patch by patch). Memory: 28 bytes a point, 8 a patch of the level.
    void sampleEach(std::span<const glm::dvec2> points, PointSpace space, int level,
                    QueryResampling resampling,
                    const std::function<void(size_t, const HeightSample&)>& emit);

    // The patch the LOD selection draws at local point `local` for `camera` and `settings`
    // (lod::PatchQuadtree::select: its id, so its level, and Err_Scr), or nullopt when no
    // selected patch covers the point (off the raster, or culled by the view frustum).
    // sample(local, PointSpace::Local, drawn->id.level) is then the surface drawn there.
    // Throws ridge::Error for settings PatchQuadtree refuses.
    std::optional<lod::SelectedPatch> drawnPatch(const lod::Camera& camera,
                                                 const lod::SelectionSettings& settings,
                                                 glm::dvec2 local) const;

  private:
    // Where a point on the raster reads its level: the covering patch and, in it, the sample
    // (nearest) or the cell and the fractions across it (bilinear).
    struct Location {
        PatchId patch;
        int u = 0, v = 0;      // sample (nearest) or the cell's first sample (bilinear)
        double fu = 0, fv = 0; // bilinear weights across the cell
    };
    int checkedLevel(int level) const;
    // Sets out.pixel, out.local and out.on_raster from `point`; true when on the raster.
    bool place(glm::dvec2 point, PointSpace space, HeightSample& out) const;
    Location locate(glm::dvec2 pixel, int level, QueryResampling resampling) const;
    // Fills out.height or out.nodata from the decoded patch.
    void read(const Location& at, const stream::DecodedPatch& patch, QueryResampling resampling,
              HeightSample& out);
    // The sample validity of a patch with kept nodata (nearest needs samples, the decoded
    // patch keeps only drawable cells), read once and cached.
    std::shared_ptr<const PatchValidity> sampleValidity(PatchId p);
    // The patches a batch's points in `level` touch (counted in first_of_), with the ancestors
    // their decodes load; counting stops past `limit`.
    size_t workingSet(int level, size_t limit) const;

    std::unique_ptr<archive::ArchiveReader> reader_;
    TerrainGeoreference georeference_;
    lod::PatchQuadtree quadtree_;
    stream::PatchLoader loader_;
    size_t cache_patches_; // what loader_ keeps
    stream::LruCache<int64_t, std::shared_ptr<const PatchValidity>> validity_{64};
    // sampleEach's scratch, kept for reuse: each point's pixel/line and patch (its index in
    // the level, kNoPatch off the raster), where each patch's points start, and the points
    // patch by patch.
    static constexpr uint32_t kNoPatch = ~uint32_t{0};
    std::vector<glm::dvec2> pixels_;
    std::vector<uint32_t> patch_of_;
    std::vector<size_t> first_of_;
    std::vector<uint32_t> order_;
};

} // namespace ridge
