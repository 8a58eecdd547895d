// HeightQuery and TerrainGeoreference on the real fixtures: the surface it reads is the
// decoded patches' (at samples exactly, bilinear between them), within the archive's bound of
// the source as GDAL reads it, at every level; coordinates in every space agree with GDAL's
// geotransform and PROJ; off-raster points are reported.
#include "test_support.h"

#include "ridge/archive/archive_reader.h"
#include "ridge/core/error.h"
#include "ridge/pipeline/build.h"
#include "ridge/pipeline/height_query.h"
#include "ridge/pipeline/level_decoder.h"

#include <gdal.h>
#include <ogr_srs_api.h>
#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace ridge;

namespace {

struct SourceRaster {
    int width = 0, height = 0;
    std::vector<double> values;
    double gt[6] = {};
    std::string wkt;
};

// The source as GDAL reads it, independently of ridge's ingest.
SourceRaster readSource(const std::string& path)
{
    GDALAllRegister();
    GDALDatasetH ds = GDALOpen(path.c_str(), GA_ReadOnly);
    if (!ds)
        throw Error("cannot open " + path);
    SourceRaster s;
    s.width = GDALGetRasterXSize(ds);
    s.height = GDALGetRasterYSize(ds);
    s.values.resize(size_t(s.width) * s.height);
    GDALRasterBandH band = GDALGetRasterBand(ds, 1);
    const CPLErr err = GDALRasterIO(band, GF_Read, 0, 0, s.width, s.height, s.values.data(),
                                    s.width, s.height, GDT_Float64, 0, 0);
    GDALGetGeoTransform(ds, s.gt);
    s.wkt = GDALGetProjectionRef(ds);
    GDALClose(ds);
    if (err != CE_None)
        throw Error("cannot read " + path);
    return s;
}

std::string buildFixture(const test::ScratchDir& dir, const std::string& source,
                         const std::string& name, const std::string& codec = "lossless",
                         std::optional<double> max_error = std::nullopt)
{
    BuildOptions o;
    o.patch_size = 33;
    o.codec = codec;
    o.max_error = max_error;
    const std::string out = dir.path(name);
    buildArchive(source, out, o);
    return out;
}

// Bilinear over a whole level grid (padding included), the reference surface.
double bilinear(const CodeGrid& grid, double i, double j)
{
    const int i0 = std::min(int(i), grid.width - 2), j0 = std::min(int(j), grid.height - 2);
    const double fx = i - i0, fy = j - j0;
    return (grid.at(i0, j0) * (1 - fx) + grid.at(i0 + 1, j0) * fx) * (1 - fy) +
           (grid.at(i0, j0 + 1) * (1 - fx) + grid.at(i0 + 1, j0 + 1) * fx) * fy;
}

} // namespace

TEST(HeightQuery, FinestSamplesAreTheDecodedOnesAndWithinTheBoundOfTheSource)
{
    test::ScratchDir dir;
    const std::string source = test::dataPath("everest_utm45.tif");
    // Lossy, so the bound is not trivially 0: every sample within max_error of GDAL's read.
    const std::string path = buildFixture(dir, source, "u.ridge", "progressive", 2.0);
    SourceRaster src = readSource(source);
    HeightQuery query(path);
    const archive::ArchiveReader& reader = query.reader();
    const int finest = reader.geometry().finestLevel();
    const CodeGrid decoded = decodeLevel(reader, finest);
    ASSERT_EQ(decoded.width, src.width);
    const double bound = reader.levelErrorBound(finest);
    EXPECT_GT(bound, 0.0);
    double worst = 0.0;
    for (int r = 0; r < src.height; ++r)
        for (int c = 0; c < src.width; ++c) {
            const HeightSample s = query.sample({c + 0.5, r + 0.5}, PointSpace::Pixel);
            ASSERT_TRUE(s.on_raster);
            ASSERT_EQ(s.level, finest);
            ASSERT_EQ(s.height, reader.quantization().toMetres(decoded.at(c, r)))
                << "sample " << c << "," << r;
            const double e = std::abs(s.height - src.values[size_t(r) * src.width + c]);
            worst = std::max(worst, e);
            ASSERT_LE(e, bound + 1e-9) << "sample " << c << "," << r;
            ASSERT_LE(e, s.error_bound + 1e-9);
        }
    EXPECT_GT(worst, 0.0); // lossy: the check above had something to check
    std::printf("progressive 2 m archive: worst |query - GDAL source| %.4f m, bound %.4f m\n",
                worst, bound);
}

TEST(HeightQuery, BetweenSamplesItIsTheBilinearSurfaceOfEveryLevel)
{
    test::ScratchDir dir;
    const std::string path = buildFixture(dir, test::dataPath("everest_crop.tif"), "e.ridge");
    HeightQuery query(path);
    const archive::ArchiveReader& reader = query.reader();
    const PyramidGeometry& g = reader.geometry();
    std::mt19937 rng(13);
    std::uniform_real_distribution<double> px(0.5, g.width() - 0.5), py(0.5, g.height() - 0.5);
    for (int level = 0; level <= g.finestLevel(); ++level) {
        const CodeGrid grid =
            decodeLevelWindow(reader, level, 0, 0, g.levelWidth(level), g.levelHeight(level));
        const double step = double(g.step(level));
        for (int k = 0; k < 400; ++k) {
            const double p = px(rng), l = py(rng);
            const HeightSample s = query.sample({p, l}, PointSpace::Pixel, level);
            ASSERT_TRUE(s.on_raster);
            const double expected = reader.quantization().toMetres(
                bilinear(grid, (p - 0.5) / step, (l - 0.5) / step));
            ASSERT_NEAR(s.height, expected, 1e-9) << "level " << level << " at " << p << "," << l;
        }
        // At the level's own samples, exactly their decoded heights.
        for (int j = 0; j < g.validLevelHeight(level); j += 3)
            for (int i = 0; i < g.validLevelWidth(level); i += 3) {
                const HeightSample s =
                    query.sample({i * step + 0.5, j * step + 0.5}, PointSpace::Pixel, level);
                ASSERT_EQ(s.height, reader.quantization().toMetres(grid.at(i, j)));
            }
    }
    EXPECT_THROW(query.sample({5, 5}, PointSpace::Pixel, g.finestLevel() + 1), Error);
}

TEST(HeightQuery, OffRasterPointsAreReportedNotThrown)
{
    test::ScratchDir dir;
    const std::string path = buildFixture(dir, test::dataPath("everest_crop.tif"), "e.ridge");
    HeightQuery query(path);
    const int w = query.reader().geometry().width(), h = query.reader().geometry().height();
    for (glm::dvec2 p : {glm::dvec2(-0.01, 5), glm::dvec2(w + 0.01, 5), glm::dvec2(5, -1e9),
                         glm::dvec2(5, h + 0.5)}) {
        const HeightSample s = query.sample(p, PointSpace::Pixel);
        EXPECT_FALSE(s.on_raster) << p.x << "," << p.y;
        EXPECT_TRUE(std::isnan(s.height));
    }
    // The outer half pixel is on the raster and reads the border sample.
    const HeightSample corner = query.sample({0, 0}, PointSpace::Pixel);
    const HeightSample first = query.sample({0.5, 0.5}, PointSpace::Pixel);
    ASSERT_TRUE(corner.on_raster);
    EXPECT_EQ(corner.height, first.height);
    EXPECT_TRUE(query.sample({double(w), double(h)}, PointSpace::Pixel).on_raster);
    // Bad input is an error, not an off-raster point.
    EXPECT_THROW(query.sample({NAN, 5}, PointSpace::Pixel), Error);
    EXPECT_THROW(query.sample({86.9, 95.0}, PointSpace::LonLat), Error);
}

TEST(TerrainGeoreference, EverySpaceAgreesWithGdalsGeotransform)
{
    test::ScratchDir dir;
    const std::string source = test::dataPath("everest_crop.tif");
    const std::string path = buildFixture(dir, source, "e.ridge");
    SourceRaster src = readSource(source);
    const archive::ArchiveReader reader(path);
    const TerrainGeoreference geo(reader);
    ASSERT_TRUE(geo.geographicCrs());
    // The Everest summit (86.925 E, 27.988 N): GDAL's inverse geotransform gives its pixel,
    // the terrain frame's x = column·spacing_x, y = (H − 1 − row)·spacing_y.
    double inv[6];
    ASSERT_TRUE(GDALInvGeoTransform(src.gt, inv));
    const double pixel = inv[0] + 86.925 * inv[1] + 27.988 * inv[2];
    const double line = inv[3] + 86.925 * inv[4] + 27.988 * inv[5];
    const glm::dvec2 local = geo.toLocal({86.925, 27.988}, PointSpace::LonLat);
    EXPECT_NEAR(local.x, (pixel - 0.5) * reader.header().spacing_x, 1e-6);
    EXPECT_NEAR(local.y, (src.height - 1 - (line - 0.5)) * reader.header().spacing_y, 1e-6);
    EXPECT_NEAR(local.x, 210.0 * reader.header().spacing_x, 1e-3); // column 210 exactly
    // The CRS of a geographic archive is lon/lat: both spaces agree.
    const glm::dvec2 crs = geo.fromLocal(local, PointSpace::Crs);
    EXPECT_NEAR(crs.x, 86.925, 1e-12);
    EXPECT_NEAR(crs.y, 27.988, 1e-12);
    EXPECT_NEAR(geo.convergenceDegrees(local), 0.0, 1e-6); // north-up lon/lat grid
}

TEST(TerrainGeoreference, LonLatRoundTripsThroughProjOnAProjectedArchive)
{
    test::ScratchDir dir;
    const std::string source = test::dataPath("everest_utm45.tif");
    const std::string path = buildFixture(dir, source, "u.ridge");
    SourceRaster src = readSource(source);
    const archive::ArchiveReader reader(path);
    const TerrainGeoreference geo(reader);
    ASSERT_TRUE(geo.hasCrs());
    ASSERT_FALSE(geo.geographicCrs());
    // GDAL's own transformation (OGR) of the summit to the raster's CRS, then its pixel.
    OGRSpatialReferenceH wgs84 = OSRNewSpatialReference(nullptr);
    OSRImportFromEPSG(wgs84, 4326);
    OSRSetAxisMappingStrategy(wgs84, OAMS_TRADITIONAL_GIS_ORDER);
    OGRSpatialReferenceH utm = OSRNewSpatialReference(src.wkt.c_str());
    OSRSetAxisMappingStrategy(utm, OAMS_TRADITIONAL_GIS_ORDER);
    OGRCoordinateTransformationH ct = OCTNewCoordinateTransformation(wgs84, utm);
    ASSERT_NE(ct, nullptr);
    double ex = 86.925, ny = 27.988;
    ASSERT_TRUE(OCTTransform(ct, 1, &ex, &ny, nullptr));
    OCTDestroyCoordinateTransformation(ct);
    OSRDestroySpatialReference(utm);
    OSRDestroySpatialReference(wgs84);
    double inv[6];
    ASSERT_TRUE(GDALInvGeoTransform(src.gt, inv));
    const double pixel = inv[0] + ex * inv[1] + ny * inv[2];
    const double line = inv[3] + ex * inv[4] + ny * inv[5];
    const glm::dvec2 summit = geo.toLocal({86.925, 27.988}, PointSpace::LonLat);
    EXPECT_NEAR(summit.x, (pixel - 0.5) * 90.0, 1e-6);
    EXPECT_NEAR(summit.y, (src.height - 0.5 - line) * 90.0, 1e-6);

    // Round trips over the whole raster and beyond: metres through lon/lat, lon/lat through
    // metres.
    double worst_m = 0.0, worst_deg = 0.0;
    for (double x = -1000; x <= 25000; x += 1300)
        for (double y = -1000; y <= 19000; y += 1100) {
            const glm::dvec2 ll = geo.fromLocal({x, y}, PointSpace::LonLat);
            const glm::dvec2 back = geo.toLocal(ll, PointSpace::LonLat);
            worst_m = std::max(worst_m, std::max(std::abs(back.x - x), std::abs(back.y - y)));
            const glm::dvec2 again = geo.fromLocal(back, PointSpace::LonLat);
            worst_deg = std::max(worst_deg, std::max(std::abs(again.x - ll.x),
                                                     std::abs(again.y - ll.y)));
        }
    EXPECT_LT(worst_m, 1e-6);
    EXPECT_LT(worst_deg, 1e-9);
    std::printf("local -> lon/lat -> local: worst %.3g m; lon/lat round trip worst %.3g deg\n",
                worst_m, worst_deg);
    // Zone 45's central meridian is 87° E. Meridians converge on the pole, which the
    // projection puts north of the central meridian: west of it, true north leans east of
    // grid north (clockwise, positive) by about (87 − 86.925)·sin(27.988°) = 0.035°.
    EXPECT_NEAR(geo.convergenceDegrees(summit), (87.0 - 86.925) * std::sin(27.988 * M_PI / 180),
                2e-4);
}

TEST(TerrainGeoreference, WithoutACrsLonLatIsAClearError)
{
    test::ScratchDir dir;
    // A PNG heightmap: no geotransform, no CRS.
    const std::string png = dir.path("plain.png");
    const std::string cmd = "gdal_translate -q -of PNG -ot UInt16 -scale 3000 9000 0 65535 " +
                            test::dataPath("everest_crop.tif") + " " + png + " 2>&1";
    ASSERT_EQ(std::system(cmd.c_str()), 0);
    std::filesystem::remove(png + ".aux.xml");
    const std::string path = buildFixture(dir, png, "p.ridge");
    HeightQuery query(path);
    EXPECT_FALSE(query.georeference().hasCrs());
    EXPECT_TRUE(query.sample({3.5, 4.5}, PointSpace::Pixel).on_raster);
    try {
        query.sample({86.9, 27.9}, PointSpace::LonLat);
        FAIL() << "lon/lat without a CRS";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("no"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
    EXPECT_THROW(query.sample({1, 1}, PointSpace::Crs), Error);
}

TEST(HeightQuery, DrawnPatchIsTheSelectionsPatchAtThePoint)
{
    test::ScratchDir dir;
    const std::string path = buildFixture(dir, test::dataPath("everest_crop.tif"), "e.ridge");
    HeightQuery query(path);
    const lod::TerrainFrame& frame = query.georeference().frame();
    const glm::dvec2 centre(frame.extentX() / 2, frame.extentY() / 2);
    lod::SelectionSettings settings;
    settings.epsilon_px = 2.0;
    // Close above the centre looking down at it: the finest level there; far away: coarser.
    const lod::Camera close({centre.x, centre.y - 10, 9500}, {centre.x, centre.y, 0}, 60.0,
                            {1920, 1080}, 1.0, 1e6);
    const lod::Camera far({centre.x, centre.y - 10, 9e5}, {centre.x, centre.y, 0}, 60.0,
                          {320, 180}, 1.0, 1e7);
    const std::optional<lod::SelectedPatch> near_patch = query.drawnPatch(close, settings, centre);
    const std::optional<lod::SelectedPatch> far_patch = query.drawnPatch(far, settings, centre);
    ASSERT_TRUE(near_patch && far_patch);
    EXPECT_LE(far_patch->screen_error, settings.epsilon_px);
    const std::optional<int> near_level = near_patch->id.level, far_level = far_patch->id.level;
    EXPECT_EQ(*near_level, query.finestLevel());
    EXPECT_LT(*far_level, *near_level);
    // Behind the far camera's frustum: nothing drawn there.
    EXPECT_FALSE(query.drawnPatch(close, settings, {-1e6, -1e6}).has_value());
    const HeightSample drawn = query.sample(centre, PointSpace::Local, *far_level);
    EXPECT_EQ(drawn.level, *far_level);
    EXPECT_LE(std::abs(drawn.height - query.sample(centre, PointSpace::Local).height),
              drawn.error_bound + 1e-6);
}
