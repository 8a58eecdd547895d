// The viewer's camera readout (apps/ridge/camera_readout.h), GL-free: each coordinate line
// labelled with its frame, the numbers those frames' conversions give, and a fly speed that
// follows the height above the ground.
#include "camera_readout.h"

#include "test_support.h"

#include "ridge/pipeline/terrain_georeference.h"

#include <gtest/gtest.h>

#include <cmath>
#include <regex>
#include <string>

using namespace ridge;

namespace {

std::string joined(const std::vector<std::string>& lines)
{
    std::string out;
    for (const std::string& l : lines)
        out += l + "\n";
    return out;
}

double number(const std::string& text, const std::string& pattern)
{
    std::smatch m;
    if (!std::regex_search(text, m, std::regex(pattern)))
        return std::nan("");
    return std::stod(m[1]);
}

} // namespace

// A projected archive: the terrain frame's metres, the CRS's easting/northing and WGS 84
// latitude/longitude, each on its own labelled line. The local metres used to read
// "123.4 E, 567.8 N", like an easting/northing.
TEST(CameraReadout, LabelsEachCoordinateWithItsFrame)
{
    test::ScratchDir dir;
    const std::string arc = dir.path("utm.ridge");
    ASSERT_EQ(
        test::runRidge("build '" + test::dataPath("everest_utm45.tif") + "' -o '" + arc + "' -q")
            .exit_code,
        0);
    const archive::ArchiveReader reader(arc);
    const cli::CameraReadout readout(reader);
    const TerrainGeoreference geo(reader);
    const glm::dvec3 camera(9876.5, 4321.0, 9100.0);
    const std::vector<std::string> lines = readout.positionLines(camera);
    const std::string text = joined(lines);
    ASSERT_EQ(lines.size(), 3u) << text;

    EXPECT_EQ(lines[0], "terrain frame: x 9876.5, y 4321.0, z 9100.0 m");
    EXPECT_EQ(lines[0].find(" E"), std::string::npos) << "local metres are no easting: " << text;

    const glm::dvec2 crs = geo.fromLocal({camera.x, camera.y}, PointSpace::Crs);
    EXPECT_EQ(lines[1].rfind("WGS 84 / UTM zone 45N (EPSG:32645): E ", 0), 0u) << text;
    EXPECT_NEAR(number(lines[1], R"(: E ([0-9.]+) m)"), crs.x, 0.006) << text;
    EXPECT_NEAR(number(lines[1], R"(, N ([0-9.]+) m)"), crs.y, 0.006) << text;

    const glm::dvec2 ll = geo.fromLocal({camera.x, camera.y}, PointSpace::LonLat);
    EXPECT_EQ(lines[2].rfind("WGS 84: ", 0), 0u) << text;
    EXPECT_NEAR(number(lines[2], R"(([0-9.]+)° N)"), ll.y, 1e-6) << text;
    EXPECT_NEAR(number(lines[2], R"(([0-9.]+)° E)"), ll.x, 1e-6) << text;
}

// A geographic archive in WGS 84 has one lon/lat line, named by its CRS; one without any
// georeferencing has the terrain frame alone.
TEST(CameraReadout, GeographicAndUngeoreferencedArchives)
{
    test::ScratchDir dir;
    const std::string arc = dir.path("geo.ridge");
    ASSERT_EQ(
        test::runRidge("build '" + test::dataPath("everest_crop.tif") + "' -o '" + arc + "' -q")
            .exit_code,
        0);
    {
        const archive::ArchiveReader reader(arc);
        const std::vector<std::string> lines =
            cli::CameraReadout(reader).positionLines({100.0, 200.0, 5000.0});
        ASSERT_EQ(lines.size(), 2u) << joined(lines);
        EXPECT_EQ(lines[1].rfind("WGS 84 (EPSG:4326): 27.8", 0), 0u) << joined(lines);
        EXPECT_NE(lines[1].find("° E"), std::string::npos) << joined(lines);
    }
    // The same heights as a plain PNG: no geotransform, no CRS.
    const std::string png = dir.path("plain.png");
    ASSERT_EQ(test::runShell("gdal_translate -q -of PNG -ot UInt16 '" +
                             test::dataPath("everest_crop.tif") + "' '" + png + "' && rm -f '" +
                             png + ".aux.xml'")
                  .exit_code,
              0);
    const std::string plain = dir.path("plain.ridge");
    ASSERT_EQ(test::runRidge("build '" + png + "' -o '" + plain + "' -q --spacing 90").exit_code,
              0);
    const archive::ArchiveReader reader(plain);
    const std::vector<std::string> lines =
        cli::CameraReadout(reader).positionLines({100.0, 200.0, 5000.0});
    ASSERT_EQ(lines.size(), 1u) << joined(lines);
    EXPECT_EQ(lines[0], "terrain frame: x 100.0, y 200.0, z 5000.0 m");
}

// The speed follows the height above the ground: a tenth of it 10 m up, a thousandth of it at
// 10 km, where it started at a fixed extent/20 m/s whatever the height (5,547 m/s over a
// 110 km tile, even on the ground).
TEST(CameraReadout, FlySpeedIsRelativeToTheHeightAboveGround)
{
    using cli::CameraReadout;
    const double rate = CameraReadout::kDefaultSpeedRate;
    EXPECT_DOUBLE_EQ(CameraReadout::flySpeed(10.0, rate), 10.0 * rate);
    EXPECT_DOUBLE_EQ(CameraReadout::flySpeed(10000.0, rate), 10000.0 * rate);
    EXPECT_DOUBLE_EQ(CameraReadout::flySpeed(10000.0, rate) / CameraReadout::flySpeed(10.0, rate),
                     1000.0);
    // On (or under) the ground it still moves, as if a couple of metres up.
    EXPECT_DOUBLE_EQ(CameraReadout::flySpeed(0.0, rate),
                     CameraReadout::kMinSpeedHeightMetres * rate);
    EXPECT_DOUBLE_EQ(CameraReadout::flySpeed(-50.0, rate), 50.0 * rate);
    // The wheel's rate is bounded.
    EXPECT_DOUBLE_EQ(CameraReadout::flySpeed(100.0, 1e9), 100.0 * CameraReadout::kMaxSpeedRate);
    EXPECT_DOUBLE_EQ(CameraReadout::flySpeed(100.0, 0.0), 100.0 * CameraReadout::kMinSpeedRate);
}
