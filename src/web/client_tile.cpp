#include "ridge/web/client_tile.h"

#include <algorithm>
#include <cmath>
#include <span>

namespace ridge::web {

namespace {

// The mesh's height at (u, v) through a bucket grid over the tile (each bucket lists the
// triangles whose bounding box meets it), so checking thousands of samples stays linear.
class MeshLocator {
  public:
    explicit MeshLocator(const QuantizedMesh& m) : m_(m), buckets_(kSide * kSide)
    {
        for (uint32_t t = 0; t + 2 < m.triangles.size(); t += 3) {
            int lo[2] = {kSide, kSide}, hi[2] = {0, 0};
            for (int k = 0; k < 3; ++k) {
                const uint32_t i = m.triangles[t + uint32_t(k)];
                for (int a = 0; a < 2; ++a) {
                    const int b = bucket(a == 0 ? m.u[i] : m.v[i]);
                    lo[a] = std::min(lo[a], b);
                    hi[a] = std::max(hi[a], b);
                }
            }
            for (int y = lo[1]; y <= hi[1]; ++y)
                for (int x = lo[0]; x <= hi[0]; ++x)
                    buckets_[size_t(y * kSide + x)].push_back(t);
        }
    }
    // The height the client draws at (u, v) (terrain_tile.h: the flattened heights'
    // interpolation plus the sphere's drop), NaN outside every triangle.
    double drawnAt(TileKey k, std::span<const double> flattened, double u, double v) const
    {
        const std::vector<uint32_t>& list = buckets_[size_t(bucket(v) * kSide + bucket(u))];
        for (uint32_t t : list)
            if (const double g = triangleValueAt(m_, t, u, v, flattened); !std::isnan(g))
                return g + sphereDrop(k, u, v);
        return NAN;
    }

  private:
    static constexpr int kSide = 32;
    static int bucket(double coordinate)
    {
        return std::clamp(int(coordinate / (QuantizedMesh::kMaxCoordinate + 1.0) * kSide), 0,
                          kSide - 1);
    }

    const QuantizedMesh& m_;
    std::vector<std::vector<uint32_t>> buckets_;
};

// The largest |drawn mesh − sample| over the level's samples inside the tile.
double measuredError(const QuantizedMesh& mesh, TileKey k,
                     const std::vector<TileSampler::LevelSample>& samples)
{
    const GeoRect r = GeographicTms::rect(k);
    const MeshLocator locate(mesh);
    const std::vector<double> flattened = flattenedHeights(mesh, k);
    double worst = 0.0;
    for (const TileSampler::LevelSample& s : samples) {
        const double u = (s.lon - r.west) / (r.east - r.west) * QuantizedMesh::kMaxCoordinate;
        const double v = (s.lat - r.south) / (r.north - r.south) * QuantizedMesh::kMaxCoordinate;
        const double h = locate.drawnAt(k, flattened, u, v);
        if (!std::isnan(h))
            worst = std::max(worst, std::abs(h - s.height));
    }
    return worst;
}

// The client draws vertices at u, v rounded to 1/32767 of the tile, up to half a unit from
// the samples they stand for, which moves the mesh by up to the slope times that shift: the
// steepest slope between neighbouring grid samples (metres a unit) times half a unit each
// way, metres.
double roundingAllowance(const TileHeights& grid)
{
    const size_t columns = grid.u.size(), rows = grid.v.size();
    double slope_u = 0.0, slope_v = 0.0; // metres per format unit
    for (size_t j = 0; j < rows; ++j)
        for (size_t i = 0; i < columns; ++i) {
            const float h = grid.heights[j * columns + i];
            if (i + 1 < columns)
                slope_u = std::max(slope_u, std::abs(grid.heights[j * columns + i + 1] - h) /
                                                double(grid.u[i + 1] - grid.u[i]));
            if (j + 1 < rows)
                slope_v = std::max(slope_v, std::abs(grid.heights[(j + 1) * columns + i] - h) /
                                                double(grid.v[j] - grid.v[j + 1]));
        }
    return 0.5 * (slope_u + slope_v);
}

} // namespace

std::optional<ClientTile> makeClientTile(TileSampler& sampler, TileKey k, int cells)
{
    // Half the client's error for the archive's bound at the level read, at most; the TIN and
    // the height step get the rest.
    const double client_error = GeographicTms::geometricError(k.z);
    std::optional<SampledTile> sampled =
        sampler.sample(k, cells, sampler.levelWithin(k.z, cells, 0.5 * client_error));
    if (!sampled)
        return std::nullopt;
    ClientTile out;
    out.level = sampled->level;
    out.archive_error = sampled->archive_error;
    out.client_error = client_error;
    out.missing = sampled->off_raster + sampled->nodata;
    // The budget the TIN may use: the client's error less the archive's bound and the
    // quantization step the tile's height range will cost.
    const auto [lo, hi] =
        std::minmax_element(sampled->grid.heights.begin(), sampled->grid.heights.end());
    const double half_step = 0.5 * double(*hi - *lo) / QuantizedMesh::kMaxCoordinate;
    double tin_bound = std::max(0.0, out.client_error - out.archive_error - half_step -
                                         roundingAllowance(sampled->grid));
    const std::vector<TileSampler::LevelSample> samples = sampler.levelSamples(k, out.level);
    // The budget above leaves roundingAllowance for the vertices' rounding; where the claim
    // still exceeds the client's error (the allowance is the grid's slope, the terrain
    // between its samples may be steeper), the TIN is made again with the excess taken off
    // its budget (twice at most; then the claim stands as measured).
    // The border lines' bound is the zoom's, not the tile's: neighbours get different
    // budgets (their own Err(P), height range and slope) but must choose the same vertices on
    // their shared edge. Half of what the client's error leaves after the level's largest
    // Err(P), which is within every tile's own budget but where a tile's height step and
    // slope take more than a quarter of the client's error.
    const double border_bound =
        std::max(0.0, 0.5 * (out.client_error - sampler.levelBound(out.level)));
    for (int attempt = 0;; ++attempt) {
        out.tile = makeTerrainTile(sampled->grid, tin_bound, border_bound);
        out.measured_error = measuredError(out.tile.mesh, k, samples);
        out.claimed_error = std::max(out.tile.error, out.measured_error) + out.archive_error;
        const double excess = out.claimed_error - out.client_error;
        if (excess <= 0.0 || tin_bound <= 0.0 || attempt == 2)
            break;
        tin_bound = std::max(0.0, tin_bound - excess - 0.01 * out.client_error);
    }
    out.grid = std::move(sampled->grid);
    out.flags = std::move(sampled->flags);
    return out;
}

} // namespace ridge::web
