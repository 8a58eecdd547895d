#pragma once
// What the web stage's tests share: the Everest fixture's archive built once per suite, and
// the test's own measure of a tile's mesh against the fixture's finest samples.
#include "fixture_archives.h"

#include "ridge/pipeline/height_query.h"
#include "ridge/web/quantized_mesh.h"
#include "ridge/web/terrain_tile.h"
#include "ridge/web/tile_grid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace ridge::test {

// A suite whose tests share one lossless Everest archive (patches of 33), built once.
class EverestArchiveSuite : public ::testing::Test {
  protected:
    static void SetUpTestSuite()
    {
        dir_ = new ScratchDir;
        archive_ = new std::string(buildEverestArchive(*dir_));
    }
    static void TearDownTestSuite()
    {
        delete archive_;
        delete dir_;
    }
    static const std::string& archive() { return *archive_; }

  private:
    static inline ScratchDir* dir_ = nullptr;
    static inline std::string* archive_ = nullptr;
};

// The largest |drawn mesh − sample| over the fixture's finest samples inside tile k (3″
// pixels from 86.7495833°E 28.0004166°N, 301 × 203), found by the test alone: its own
// positions, the sample whose pixel it is, drawnHeightAt's brute-force search.
inline double everestMeshError(const web::QuantizedMesh& m, web::TileKey k, HeightQuery& finest)
{
    const web::GeoRect r = web::GeographicTms::rect(k);
    const std::vector<double> flattened = web::flattenedHeights(m, k);
    const double step = 3.0 / 3600.0;
    double worst = 0.0;
    for (int j = 0; j < 203; ++j)
        for (int i = 0; i < 301; ++i) {
            const double lon = 86.749583333333334 + (i + 0.5) * step;
            const double lat = 28.000416666666666 - (j + 0.5) * step;
            if (lat > r.north || lat < r.south || lon < r.west || lon > r.east)
                continue;
            const HeightSample s =
                finest.sample({i + 0.5, j + 0.5}, PointSpace::Pixel, -1, QueryResampling::Nearest);
            if (!s.on_raster || s.nodata)
                continue;
            const double u =
                (lon - r.west) / (r.east - r.west) * web::QuantizedMesh::kMaxCoordinate;
            const double v =
                (lat - r.south) / (r.north - r.south) * web::QuantizedMesh::kMaxCoordinate;
            worst = std::max(worst, std::abs(web::drawnHeightAt(m, k, flattened, u, v) - s.height));
        }
    return worst;
}

} // namespace ridge::test
