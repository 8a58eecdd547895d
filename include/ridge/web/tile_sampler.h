#pragma once
// Height grids of web tiles read from an archive (GL-free; one sampler per thread, as the
// HeightQuery it owns is not thread-safe).
//
// A geographic tile of zoom z asked for with `cells` cells a side reads the archive level
// whose sample spacing is the finest not finer than that (levelFor). Where the archive is a
// north-up longitude/latitude grid (SRTM, Copernicus, ETOPO), the tile's grid is that level's
// own samples inside the tile (cells to 2·cells of them a side) plus the tile's four edges,
// read bilinearly between the samples around them: the mesh's bound then holds at the data.
// Elsewhere (projected archives) it is a uniform grid of `cells` cells read through PROJ,
// whose samples are the level's surface between its samples. Either way a sample is within
// Err(P) of the finest samples. A sample off the raster takes the raster's edge height (the
// point clamped into the raster) faded linearly to 0 m over the raster's own size beyond it —
// no cliff at the data's edge, no plateau across the rest of the globe — and one on kept
// nodata the value the archive stores there; both are functions of the position alone, so
// two tiles read a shared edge alike (a root tile the archive misses included), and both are
// counted.
//
// Heights are the archive's: above the ellipsoid when the build shifted them there
// (`ridge build --vertical-datum`, "build.vertical_shift"), else above whatever the source
// measured from (verticalReference()).
#include "ridge/io/geoid_model.h"
#include "ridge/pipeline/height_query.h"
#include "ridge/web/terrain_tile.h"
#include "ridge/web/tile_grid.h"

#include <array>
#include <memory>
#include <optional>
#include <span>
#include <string>

namespace ridge::web {

struct SampledTile {
    TileHeights grid;
    int level = 0;             // the archive level read
    double archive_error = 0.; // the largest Err(P) of the patches read, metres
    size_t off_raster = 0;     // samples outside the archive (the raster's edge goes on there)
    size_t nodata = 0;         // samples on kept nodata (the value the archive stores there)
    // Per grid sample (grid.heights' order): kAbsent off the raster or on kept nodata, kWater
    // where the archive's sample flags say water (bilinear rule, HeightSample::water).
    static constexpr uint8_t kAbsent = 1, kWater = 2;
    std::vector<uint8_t> flags;
};

// A Web Mercator tile's heights at its pixel centres (terrain_rgb.h).
struct MercatorSamples {
    int size = 0;
    std::vector<float> heights; // size × size, row 0 north, metres; missing ones filled
    int level = 0;              // the archive level read
    double archive_error = 0.;  // the largest Err(P) of the patches read, metres
    size_t missing = 0;         // pixels off the raster (its edge's height) or on kept nodata
                                // (the archive's fill there)
};

class TileSampler {
  public:
    // Opens the archive; throws ridge::Error when it cannot be read or has no
    // longitude/latitude (no CRS or geotransform).
    explicit TileSampler(const std::string& archive_path,
                         size_t cache_patches = HeightQuery::kDefaultCachePatches);

    const archive::ArchiveReader& reader() const { return query_.reader(); }
    // The archive's longitude/latitude box, degrees (its border traced through PROJ; a
    // grid in 0..360° E keeps longitudes past 180°).
    const GeoRect& extent() const { return extent_; }
    // "ellipsoid" when heights are above WGS 84's ellipsoid, else the archive's vertical datum
    // name ("EGM96 height", ...) or "unknown" — of the archive, whatever toEllipsoid did.
    std::string verticalReference() const;
    // The EPSG code of the archive's vertical datum, when it names one and its heights are
    // not already ellipsoidal.
    std::optional<int> verticalDatumEpsg() const;
    // From now on sample() and levelSamples() give heights above the WGS 84 ellipsoid: the
    // archive's heights (above vertical datum `epsg`, named `name`) plus the geoid's N at each
    // point, through PROJ (io::GeoidModel). Terrain-RGB (sampleMercator) keeps the archive's
    // heights. Throws ridge::Error when PROJ cannot (a grid missing). Returns PROJ's name of
    // the transformation.
    std::string toEllipsoid(int epsg, const std::string& name);
    // Whether geographic tile `k` overlaps the archive.
    bool overlaps(TileKey k) const;
    // The archive level a tile of zoom k.z with `cells` cells reads (see above).
    int levelFor(TileKey k, int cells) const;
    // The largest Err(P) of the level's patches (from the index, no patch read): how far that
    // level's surface may lie from the finest samples anywhere.
    double levelBound(int level) const;
    // levelFor, or a finer level where that one's largest Err(P) exceeds `error` (the
    // coarsest finer level within it), while a tile of the zoom stays within kMaxTileSamples
    // samples a side: coarse levels of rough terrain lie hundreds of metres from the finest
    // samples, more than a client's error for the zoom, even where their spacing suits the
    // tile. One level for every tile of a zoom: neighbours must sample their shared edge on
    // the same level's samples, or their edge vertices differ (a T-junction; a per-tile
    // choice made one on the Everest fixture at zoom 10).
    static constexpr int kMaxTileSamples = 1024;
    int levelWithin(int zoom, int cells, double error) const;
    // The deepest zoom whose tiles of `cells` cells are still no finer than the archive's
    // finest samples (deeper tiles add nothing but interpolation).
    int maxZoom(int cells) const;
    // The tile's grid (any tile: one the archive misses reads its edge fading out), or
    // nullopt when none of its points could be placed on the raster (PROJ refused them all).
    // Throws ridge::Error for an invalid key or cells outside [1, 4096].
    // `level` < 0: levelFor's; else that level (throws ridge::Error past the finest).
    std::optional<SampledTile> sample(TileKey k, int cells, int level = -1);

    // Web Mercator XYZ tiles of `size` pixels a side (terrain-RGB): whether tile k overlaps
    // the archive; the level read (the finest not finer than the tile's pixels at its centre
    // latitude); the deepest zoom whose pixels at the archive's centre latitude are no finer
    // than its finest samples; the heights at the pixel centres (bilinear on that level), or
    // nullopt when the tile misses the archive. Throw ridge::Error for an invalid key or a
    // size outside [1, 4096].
    bool overlapsMercator(TileKey k) const;
    int levelForMercator(TileKey k, int size) const;
    int maxMercatorZoom(int size) const;
    std::optional<MercatorSamples> sampleMercator(TileKey k, int size);

    // The archive level's own valid samples inside tile `k` (longitude, latitude, height):
    // what a tile's mesh is checked against between its grid's samples. At most `limit`
    // (the first rows of the window past that). Throws ridge::Error for an invalid key or a
    // level beyond the finest.
    struct LevelSample {
        double lon = 0, lat = 0, height = 0;
    };
    std::vector<LevelSample> levelSamples(TileKey k, int level, size_t limit = 1 << 20);

  private:
    double finestSpacingMetres() const;
    bool overlapsRect(const GeoRect& r) const;
    // The coarsest level whose spacing is not coarser than `metres` (the finest when none).
    int levelForSpacing(double metres) const;
    // The finest pixel/line box the tile's outline covers (a projected archive's is curved).
    std::pair<glm::dvec2, glm::dvec2> pixelWindow(TileKey k) const;
    // Puts grid's lines on the level's own sample columns and rows inside tile k (plus its
    // edges, and evenly spaced lines in gaps wider than a `cells` grid's cell) and points_ on their
    // pixel/line; false (nothing set) where the archive is not a north-up longitude/latitude grid
    // or the tile falls outside its period.
    bool placeOnSamples(TileKey k, int level, int cells, TileHeights& grid);

    // Reads points_ (given in `space`; left as pixel/line) on `level`, bilinear: a valid
    // sample its height; kept nodata the value the archive stores there; a point off the
    // raster the raster's edge (the point clamped into it) — each a function of the position
    // alone, so tiles sharing an edge read it alike. flags: SampledTile's. valid_ marks what
    // was read; points PROJ cannot place are left for the caller to fill. Returns how many
    // were read.
    size_t readPoints(PointSpace space, int level, std::vector<float>& heights,
                      std::vector<uint8_t>& flags, double& archive_error, size_t& off_raster,
                      size_t& nodata);
    // Adds N to heights[i] at points_[i] (given in `space`) when toEllipsoid was called.
    void addUndulations(std::span<float> heights, PointSpace space);

    HeightQuery query_;
    std::unique_ptr<io::GeoidModel> geoid_; // set by toEllipsoid
    std::vector<double> level_bounds_;      // levelBound, per level
    std::vector<std::array<double, 2>> lonlat_;
    std::vector<double> undulations_;
    GeoRect extent_;
    bool north_up_geographic_ = false; // lon/lat CRS, unrotated geotransform
    std::vector<glm::dvec2> points_;   // scratch, reused across tiles
    std::vector<HeightSample> samples_;
    std::vector<uint8_t> valid_, unreadable_, outside_;
    std::vector<double> fade_; // per point off the raster: how much of the edge's height it keeps
};

} // namespace ridge::web
