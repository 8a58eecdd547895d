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
#include <gtest/gtest.h>
#include <ogr_srs_api.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>

using namespace ridge;

namespace {

struct SourceRaster {
    int width = 0, height = 0;
    std::vector<double> values;
    double gt[6] = {};
    std::string wkt;
    std::optional<double> nodata;
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
    int has_nodata = 0;
    const double nodata = GDALGetRasterNoDataValue(band, &has_nodata);
    if (has_nodata)
        s.nodata = nodata;
    GDALClose(ds);
    if (err != CE_None)
        throw Error("cannot read " + path);
    return s;
}

std::string buildFixture(const test::ScratchDir& dir, const std::string& source,
                         const std::string& name, const std::string& codec = "lossless",
                         std::optional<double> max_error = std::nullopt,
                         io::VoidFill fill = io::VoidFill::Interior)
{
    BuildOptions o;
    o.patch_size = 33;
    o.codec = codec;
    o.max_error = max_error;
    o.ingest.fill_voids = fill;
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
            const double expected =
                reader.quantization().toMetres(bilinear(grid, (p - 0.5) / step, (l - 0.5) / step));
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

// A grid that goes round the Earth (the 2° globe fixture, 0..360° with column 0 repeated):
// a longitude in any period reads what is drawn there, across the antimeridian and the
// grid's own edge meridian; a regional grid does not wrap.
TEST(HeightQuery, LongitudesWrapOnAGridThatGoesRoundTheEarth)
{
    test::ScratchDir dir;
    const std::string path =
        buildFixture(dir, test::dataPath("etopo5_globe_181x91.tif"), "globe.ridge");
    HeightQuery query(path);
    for (const glm::dvec2 p : {glm::dvec2(-150.0, 20.0), glm::dvec2(-179.0, -30.0),
                               glm::dvec2(-1.0, 50.0), glm::dvec2(-0.5, 0.0)}) {
        const HeightSample west = query.sample(p, PointSpace::LonLat);
        const HeightSample east = query.sample({p.x + 360.0, p.y}, PointSpace::LonLat);
        ASSERT_TRUE(west.on_raster) << p.x << ", " << p.y;
        ASSERT_TRUE(east.on_raster) << p.x + 360.0 << ", " << p.y;
        EXPECT_EQ(west.height, east.height) << p.x << ", " << p.y;
    }
    // On a sample (a 2° grid: −150° is column 105 of 0..360°), the sample itself.
    const HeightSample at = query.sample({-150.0, 20.0}, PointSpace::LonLat);
    const HeightSample pixel = query.sample({105.5, 35.5}, PointSpace::Pixel);
    EXPECT_EQ(at.height, pixel.height);

    // Everest's crop is regional: west of it is off the raster, not wrapped round.
    const std::string crop = buildFixture(dir, test::dataPath("everest_crop.tif"), "e.ridge");
    HeightQuery regional(crop);
    EXPECT_FALSE(regional.sample({86.925 - 360.0, 27.988}, PointSpace::LonLat).on_raster);
    EXPECT_TRUE(regional.sample({86.925, 27.988}, PointSpace::LonLat).on_raster);
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
            worst_deg =
                std::max(worst_deg, std::max(std::abs(again.x - ll.x), std::abs(again.y - ll.y)));
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
    const lod::Camera far({centre.x, centre.y - 10, 9e5}, {centre.x, centre.y, 0}, 60.0, {320, 180},
                          1.0, 1e7);
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

namespace {

// CRS points whose GDAL pixel is known: random ones, and ones exactly on pixel edges and
// corners (x = gt0 + i·gt1 as GDAL would compute it), where the pixel depends on the last
// bit of the inverse geotransform.
std::vector<glm::dvec2> crsPointsOf(const SourceRaster& src, int count, unsigned seed)
{
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<glm::dvec2> points;
    for (int k = 0; k < count; ++k) {
        const double p = u(rng) * src.width, l = u(rng) * src.height;
        points.push_back(
            {src.gt[0] + p * src.gt[1] + l * src.gt[2], src.gt[3] + p * src.gt[4] + l * src.gt[5]});
    }
    for (int i = 0; i < src.width; i += 7)
        for (int j = 0; j < src.height; j += 5)
            points.push_back({src.gt[0] + i * src.gt[1] + j * src.gt[2],
                              src.gt[3] + i * src.gt[4] + j * src.gt[5]});
    return points;
}

// gdallocationinfo -geoloc's pixel of a CRS point (its GDALInvGeoTransform and floor), or
// nullopt off the raster ("Location is off this file").
std::optional<std::array<int, 2>> gdalPixel(const SourceRaster& src, glm::dvec2 p)
{
    double inv[6];
    if (!GDALInvGeoTransform(const_cast<double*>(src.gt), inv))
        throw Error("singular geotransform");
    const int pixel = int(std::floor(inv[0] + inv[1] * p.x + inv[2] * p.y));
    const int line = int(std::floor(inv[3] + inv[4] * p.x + inv[5] * p.y));
    if (pixel < 0 || line < 0 || pixel >= src.width || line >= src.height)
        return std::nullopt;
    return std::array<int, 2>{pixel, line};
}

} // namespace

TEST(TerrainGeoreference, CrsToPixelIsGdalsInverseGeotransformBitForBit)
{
    // GDALInvGeoTransform inverts a north-up geotransform without the determinant; the
    // determinant's algebra gives 1199.9999999999998 pixels a degree instead of 1200 for a
    // 3" grid, which puts a point on a pixel edge in the pixel before GDAL's.
    test::ScratchDir dir;
    for (const std::string name : {"everest_crop.tif", "everest_utm45.tif"}) {
        const SourceRaster src = readSource(test::dataPath(name));
        const std::string path = buildFixture(dir, test::dataPath(name), name + ".ridge");
        const archive::ArchiveReader reader(path);
        const TerrainGeoreference geo(reader);
        double inv[6];
        ASSERT_TRUE(GDALInvGeoTransform(const_cast<double*>(src.gt), inv));
        for (const glm::dvec2 p : crsPointsOf(src, 500, 5)) {
            const glm::dvec2 pixel = geo.toPixel(p, PointSpace::Crs);
            ASSERT_EQ(pixel.x, inv[0] + inv[1] * p.x + inv[2] * p.y) << name;
            ASSERT_EQ(pixel.y, inv[3] + inv[4] * p.x + inv[5] * p.y) << name;
        }
    }
}

TEST(HeightQuery, NearestIsTheSampleGdalReportsAtEveryPoint)
{
    // A lossless archive of an Int16 source: nearest answers the source sample of the pixel
    // gdallocationinfo picks, exactly, at random points and on every pixel edge tried.
    test::ScratchDir dir;
    for (const std::string name : {"everest_crop.tif", "everest_utm45.tif"}) {
        const SourceRaster src = readSource(test::dataPath(name));
        HeightQuery query(buildFixture(dir, test::dataPath(name), name + ".ridge"));
        const std::vector<glm::dvec2> points = crsPointsOf(src, 3000, 11);
        std::vector<HeightSample> batch(points.size());
        query.sampleBatch(points, PointSpace::Crs, -1, QueryResampling::Nearest, batch);
        int compared = 0;
        for (size_t k = 0; k < points.size(); ++k) {
            const std::optional<std::array<int, 2>> px = gdalPixel(src, points[k]);
            const HeightSample one =
                query.sample(points[k], PointSpace::Crs, -1, QueryResampling::Nearest);
            if (!px) // off the file for GDAL: ridge's raster edge (P = width) or beyond
                continue;
            const double expected = src.values[size_t((*px)[1]) * src.width + size_t((*px)[0])];
            ASSERT_TRUE(one.on_raster && !one.nodata) << name << " point " << k;
            ASSERT_EQ(one.height, expected)
                << name << " point " << k << " pixel " << (*px)[0] << "," << (*px)[1];
            ASSERT_EQ(batch[k].height, expected) << name << " point " << k;
            ++compared;
        }
        EXPECT_GT(compared, 3000) << name;
    }
}

TEST(HeightQuery, NearestAtACoarserLevelIsItsNearestDecodedSample)
{
    test::ScratchDir dir;
    const std::string path = buildFixture(dir, test::dataPath("everest_crop.tif"), "e.ridge");
    HeightQuery query(path);
    const archive::ArchiveReader& reader = query.reader();
    const PyramidGeometry& g = reader.geometry();
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> px(0.0, g.width()), py(0.0, g.height());
    for (int level = 0; level < g.finestLevel(); ++level) {
        const CodeGrid grid =
            decodeLevelWindow(reader, level, 0, 0, g.levelWidth(level), g.levelHeight(level));
        const int64_t step = g.step(level);
        for (int k = 0; k < 300; ++k) {
            const glm::dvec2 p(px(rng), py(rng));
            const HeightSample s =
                query.sample(p, PointSpace::Pixel, level, QueryResampling::Nearest);
            // The level sample at the smallest distance along each axis, its position clamped
            // to the last finest sample (pyramid_geometry.h).
            auto nearest = [&](double c, int last, int samples) {
                int best = 0;
                for (int i = 1; i < samples; ++i)
                    if (std::abs(double(std::min<int64_t>(i * step, last)) - c) <=
                        std::abs(double(std::min<int64_t>(best * step, last)) - c))
                        best = i;
                return best;
            };
            const int i = nearest(std::clamp(p.x - 0.5, 0.0, g.width() - 1.0), g.width() - 1,
                                  g.levelWidth(level));
            const int j = nearest(std::clamp(p.y - 0.5, 0.0, g.height() - 1.0), g.height() - 1,
                                  g.levelHeight(level));
            ASSERT_EQ(s.height, reader.quantization().toMetres(grid.at(i, j)))
                << "level " << level << " at " << p.x << "," << p.y;
        }
    }
}

TEST(HeightQuery, NearestNodataIsExactlyTheSourcesNodataSamples)
{
    // Kept nodata: the warped fixture's collar (border-connected) by default, the Rainier
    // voids with fill "none". Nearest is nodata exactly where the source sample is; bilinear
    // also where a cell around the point touches one (never drawn there).
    test::ScratchDir dir;
    const struct {
        const char* name;
        io::VoidFill fill;
    } cases[] = {{"everest_utm44.tif", io::VoidFill::Interior},
                 {"rainier_voids.tif", io::VoidFill::None}};
    for (const auto& c : cases) {
        const SourceRaster src = readSource(test::dataPath(c.name));
        ASSERT_TRUE(src.nodata.has_value()) << c.name;
        HeightQuery query(buildFixture(dir, test::dataPath(c.name), std::string(c.name) + ".ridge",
                                       "lossless", std::nullopt, c.fill));
        std::vector<glm::dvec2> centres;
        for (int r = 0; r < src.height; ++r)
            for (int col = 0; col < src.width; ++col)
                centres.push_back({col + 0.5, r + 0.5});
        std::vector<HeightSample> nearest(centres.size()), bilinear(centres.size());
        query.sampleBatch(centres, PointSpace::Pixel, -1, QueryResampling::Nearest, nearest);
        query.sampleBatch(centres, PointSpace::Pixel, -1, QueryResampling::Bilinear, bilinear);
        int voids = 0, cell_nodata = 0;
        for (size_t k = 0; k < centres.size(); ++k) {
            const double value = src.values[k];
            const bool is_void = value == *src.nodata;
            voids += is_void;
            ASSERT_EQ(nearest[k].nodata, is_void) << c.name << " sample " << k;
            if (!is_void) {
                ASSERT_EQ(nearest[k].height, value) << c.name << " sample " << k;
            } else { // a void sample has no drawable cell around it: bilinear agrees there
                ASSERT_TRUE(bilinear[k].nodata) << c.name << " sample " << k;
            }
            cell_nodata += bilinear[k].nodata && !is_void;
        }
        EXPECT_GT(voids, 300) << c.name;
        // Data samples on a void's rim: no drawn cell holds them, nearest still answers.
        EXPECT_GT(cell_nodata, 0) << c.name;
    }
}

TEST(HeightQuery, BatchAnswersWhatSampleAnswersInInputOrder)
{
    test::ScratchDir dir;
    const std::string path =
        buildFixture(dir, test::dataPath("everest_utm44.tif"), "u.ridge", "progressive", 1.0);
    HeightQuery batch_query(path, 1), one_query(path);
    const PyramidGeometry& g = one_query.reader().geometry();
    std::mt19937 rng(17);
    std::uniform_real_distribution<double> px(-5.0, g.width() + 5.0), py(-5.0, g.height() + 5.0);
    std::vector<glm::dvec2> points;
    for (int k = 0; k < 4000; ++k)
        points.push_back({px(rng), py(rng)});
    points.push_back({NAN, 3.0}); // invalid: reported, the batch goes on
    points.push_back({3.0, INFINITY});
    for (const QueryResampling r : {QueryResampling::Bilinear, QueryResampling::Nearest})
        for (const int level : {-1, 1}) {
            std::vector<HeightSample> out(points.size());
            batch_query.sampleBatch(points, PointSpace::Pixel, level, r, out);
            int on = 0, off = 0, nodata = 0;
            for (size_t k = 0; k < points.size(); ++k) {
                const HeightSample& b = out[k];
                if (!std::isfinite(points[k].x) || !std::isfinite(points[k].y)) {
                    EXPECT_TRUE(b.invalid_point);
                    EXPECT_FALSE(b.on_raster);
                    EXPECT_THROW(one_query.sample(points[k], PointSpace::Pixel, level, r), Error);
                    continue;
                }
                const HeightSample s = one_query.sample(points[k], PointSpace::Pixel, level, r);
                ASSERT_FALSE(b.invalid_point);
                ASSERT_EQ(b.on_raster, s.on_raster) << k;
                ASSERT_EQ(b.nodata, s.nodata) << k;
                ASSERT_EQ(b.pixel, s.pixel) << k;
                ASSERT_EQ(b.local, s.local) << k;
                ASSERT_EQ(b.level, s.level) << k;
                if (s.on_raster) {
                    ASSERT_EQ(b.patch, s.patch) << k;
                    ASSERT_EQ(b.error_bound, s.error_bound) << k;
                }
                if (s.on_raster && !s.nodata) {
                    ASSERT_EQ(b.height, s.height) << k;
                }
                on += s.on_raster && !s.nodata;
                off += !s.on_raster;
                nodata += s.nodata;
            }
            EXPECT_GT(on, 2000);
            EXPECT_GT(off, 50);
            EXPECT_GT(nodata, 100); // the collar
        }
    std::vector<HeightSample> short_out(3);
    EXPECT_THROW(
        batch_query.sampleBatch(points, PointSpace::Pixel, -1, QueryResampling::Nearest, short_out),
        Error);
    EXPECT_THROW(batch_query.sampleBatch(points, PointSpace::Pixel, g.finestLevel() + 1,
                                         QueryResampling::Nearest, std::span<HeightSample>()),
                 Error);
}

TEST(HeightQuery, BatchDecodesEachPatchOnceWhateverTheCache)
{
    // Random points over every patch with the smallest cache: point by point, nearly every
    // point decodes its patch again; in a batch each patch is decoded once (a lossless
    // archive: no ancestor chains).
    test::ScratchDir dir;
    const std::string path = buildFixture(dir, test::dataPath("everest_crop.tif"), "e.ridge");
    HeightQuery query(path, 1);
    const PyramidGeometry& g = query.reader().geometry();
    std::mt19937 rng(23);
    std::uniform_real_distribution<double> px(0.0, g.width()), py(0.0, g.height());
    std::vector<glm::dvec2> points;
    for (int k = 0; k < 20000; ++k)
        points.push_back({px(rng), py(rng)});
    std::vector<HeightSample> out(points.size());
    const uint64_t before = query.loaderStats().decoded;
    query.sampleBatch(points, PointSpace::Pixel, -1, QueryResampling::Bilinear, out);
    const uint64_t decoded = query.loaderStats().decoded - before;
    std::set<int64_t> touched;
    for (const HeightSample& s : out)
        touched.insert(g.patchIndex(s.patch));
    EXPECT_EQ(decoded, touched.size());
    EXPECT_EQ(int64_t(touched.size()), g.patchCount(g.finestLevel()));

    // Progressive, with a cache that holds what the points touch and every ancestor their
    // decodes load: read in input order, each of those decoded exactly once.
    const std::string progressive =
        buildFixture(dir, test::dataPath("everest_crop.tif"), "p.ridge", "progressive", 1.0);
    HeightQuery roomy(progressive, 1000);
    const uint64_t start = roomy.loaderStats().decoded;
    roomy.sampleBatch(points, PointSpace::Pixel, -1, QueryResampling::Nearest, out);
    std::set<int64_t> chain;
    for (const HeightSample& s : out)
        for (PatchId p = s.patch;; p = p.parent()) {
            chain.insert(g.patchIndex(p));
            if (p.level == 0)
                break;
        }
    EXPECT_EQ(roomy.loaderStats().decoded - start, chain.size());
}
