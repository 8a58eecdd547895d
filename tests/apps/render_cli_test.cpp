// `ridge render` as a user runs it: a picture of real terrain, JSON statistics, and clear
// errors (naming the file) with nothing left behind for every bad input.
#include "test_support.h"

#include <gdal.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <vector>

using namespace ridge;
namespace fs = std::filesystem;

namespace {

std::string buildEverest(const test::ScratchDir& dir)
{
    return test::buildEverestWithCli(dir, "everest.ridge", "--patch 33");
}

void expectRenderRejected(const test::ScratchDir& dir, const std::string& args,
                          const std::string& phrase)
{
    const std::string out = dir.path("bad.png");
    const test::CommandResult r = test::runRidge("render " + args + " -o '" + out + "'");
    EXPECT_NE(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find(phrase), std::string::npos)
        << "expected '" << phrase << "' in: " << r.output;
    EXPECT_EQ(r.output.find("Segmentation"), std::string::npos);
    for (const auto& entry : fs::directory_iterator(dir.dir()))
        EXPECT_NE(entry.path().filename().string().rfind("bad.png", 0), 0u)
            << "left behind: " << entry.path();
}

// 'path', for a command line (GCC 12 warns falsely on "'" + temporary + "'").
std::string quoted(const std::string& path)
{
    std::string q = "'";
    q += path;
    q += "'";
    return q;
}

} // namespace

TEST(RenderCli, RendersAPngOfTheRequestedSizeAndReportsTheFrameAsJson)
{
    test::ScratchDir dir;
    const std::string arc = buildEverest(dir);
    const std::string png = dir.path("view.png");
    const auto t0 = std::chrono::steady_clock::now();
    const test::CommandResult r =
        test::runRidgeStdout("render '" + arc + "' -o '" + png +
                             "' --size 400x250 --error 1.5 --camera 2000,-3000,9000 "
                             "--look-at 12000,9000,5000 --json");
    const double wall_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    ASSERT_EQ(r.exit_code, 0) << r.output;
    // --json: the document alone on stdout (the convention of every command).
    const nlohmann::json j = nlohmann::json::parse(r.output);
    // GPU times are durations inside the run, or null where not measured (never the GPU
    // clock itself: gpu_upload_ms once read back llvmpipe's time since boot).
    for (const char* key : {"gpu_ms", "gpu_upload_ms", "cpu_select_ms", "cpu_load_ms"}) {
        ASSERT_TRUE(j.contains(key)) << key;
        if (!j[key].is_null()) {
            EXPECT_GE(j[key].get<double>(), 0.0) << key;
            EXPECT_LE(j[key].get<double>(), wall_ms) << key;
        }
    }
    EXPECT_FALSE(j["gpu_upload_ms"].is_null()) << "the first frame uploads its patches";
    EXPECT_EQ(j["size"][0], 400);
    EXPECT_EQ(j["size"][1], 250);
    EXPECT_DOUBLE_EQ(j["camera"][2].get<double>(), 9000.0);
    EXPECT_DOUBLE_EQ(j["epsilon_px"].get<double>(), 1.5);
    EXPECT_GT(j["patches"].get<int>(), 0);
    EXPECT_GT(j["triangles"].get<int>(), 1000);
    GDALAllRegister();
    GDALDatasetH ds = GDALOpen(png.c_str(), GA_ReadOnly);
    ASSERT_NE(ds, nullptr);
    EXPECT_EQ(GDALGetRasterXSize(ds), 400);
    EXPECT_EQ(GDALGetRasterYSize(ds), 250);
    EXPECT_EQ(GDALGetRasterCount(ds), 3);
    GDALClose(ds);
}

TEST(RenderCli, DebugModesAndTheDefaultCameraRender)
{
    test::ScratchDir dir;
    const std::string arc = buildEverest(dir);
    for (const std::string extra :
         {"--mode lod", "--mode tess --wireframe", "--no-sky --no-fog --no-skirts --samples 1"}) {
        const test::CommandResult r = test::runRidge(
            "render '" + arc + "' -o '" + dir.path("m.png") + "' --size 160x90 -q " + extra);
        EXPECT_EQ(r.exit_code, 0) << extra << ": " << r.output;
        EXPECT_TRUE(fs::exists(dir.path("m.png"))) << extra;
    }
}

TEST(RenderCli, BadInputsGetAClearErrorANonZeroExitAndNoPicture)
{
    test::ScratchDir dir;
    const std::string arc = buildEverest(dir);
    expectRenderRejected(dir, quoted(dir.path("missing.ridge")), "missing.ridge");
    {
        std::ofstream(dir.path("junk.ridge")) << "not an archive at all, just some text to read";
    }
    expectRenderRejected(dir, quoted(dir.path("junk.ridge")), "junk.ridge");
    // A corrupt root patch: the renderer decodes it first.
    fs::copy_file(arc, dir.path("corrupt.ridge"));
    {
        std::fstream f(dir.path("corrupt.ridge"), std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(200);
        f.put('\x5a');
    }
    expectRenderRejected(dir, quoted(dir.path("corrupt.ridge")), "corrupt.ridge");
    expectRenderRejected(dir, "'" + arc + "' --size 100by50", "--size");
    expectRenderRejected(dir, "'" + arc + "' --size 0x50", "size");
    expectRenderRejected(dir, "'" + arc + "' --mode fancy", "--mode");
    expectRenderRejected(dir, "'" + arc + "' --look-at 1,2,3", "--look-at requires --camera");
    expectRenderRejected(dir, "'" + arc + "' --camera 1,2", "--camera");
    expectRenderRejected(dir, "'" + arc + "' --camera 5,5,5 --look-at 5,5,5", "coincide");
    expectRenderRejected(dir, "'" + arc + "' --error 0", "--error");
    // An unwritable output: the directory does not exist.
    const test::CommandResult r = test::runRidge("render '" + arc + "' -o '" +
                                                 dir.path("no/such/dir/x.png") + "' --size 64x64");
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.output.find("x.png"), std::string::npos) << r.output;
}

// The default camera left the terrain a fifth of the frame (a sixth of its pixels at
// 640 x 360 on the Everest tile): it framed the terrain's bounding box, which the summit makes
// tall and mostly empty. Measured on the picture: pixels that are not the plain background.
TEST(RenderCli, TheDefaultViewFillsTheFrameWithTheTerrain)
{
    test::ScratchDir dir;
    const std::string arc = test::buildEverestWithCli(dir, "everest.ridge", "");
    const std::string png = dir.path("default.png");
    const test::CommandResult r = test::runRidge("render " + quoted(arc) + " -o " + quoted(png) +
                                                 " --size 640x360 --no-sky --no-fog -q");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    GDALAllRegister();
    GDALDatasetH ds = GDALOpen(png.c_str(), GA_ReadOnly);
    ASSERT_NE(ds, nullptr);
    const int w = GDALGetRasterXSize(ds), h = GDALGetRasterYSize(ds);
    std::vector<uint8_t> rgb(size_t(w) * h * 3);
    ASSERT_EQ(GDALDatasetRasterIO(ds, GF_Read, 0, 0, w, h, rgb.data(), w, h, GDT_Byte, 3, nullptr,
                                  3, w * 3, 1),
              CE_None);
    GDALClose(ds);
    // The top-left corner is background: the view keeps a 4 % margin around the terrain.
    size_t terrain = 0;
    int x0 = w, x1 = -1, y0 = h, y1 = -1;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const size_t i = (size_t(y) * w + x) * 3;
            if (rgb[i] != rgb[0] || rgb[i + 1] != rgb[1] || rgb[i + 2] != rgb[2]) {
                ++terrain;
                x0 = std::min(x0, x);
                x1 = std::max(x1, x);
                y0 = std::min(y0, y);
                y1 = std::max(y1, y);
            }
        }
    EXPECT_GE(double(terrain) / (double(w) * h), 0.35);
    // Spanning the picture on one axis, clear of its edges.
    EXPECT_TRUE(x1 - x0 > 0.85 * w || y1 - y0 > 0.85 * h)
        << x0 << ".." << x1 << " x " << y0 << ".." << y1;
    EXPECT_GT(x0, 0);
    EXPECT_GT(y0, 0);
    EXPECT_LT(x1, w - 1);
}

// The globe from the command line (issue 26): a raster that goes round the Earth renders on the
// ellipsoid by default and says so; cameras given in longitude/latitude, below the ellipsoid
// and at the Earth's centre render without a NaN reaching the picture's numbers; a frame that
// cannot be had is refused by name, with exit status 2 for a malformed --frame.
TEST(RenderCli, TheGlobeRendersOnTheEllipsoidAndRefusesWhatCannotLieOnIt)
{
    test::ScratchDir dir;
    const std::string globe = dir.path("globe.ridge");
    const test::CommandResult b =
        test::runRidge("build " + quoted(test::dataPath("etopo5_globe_181x91.tif")) + " -o " +
                       quoted(globe) + " --patch 17 -q");
    ASSERT_EQ(b.exit_code, 0) << b.output;
    auto render = [&](const std::string& args) {
        return test::runRidge("render " + quoted(globe) + " -o " + quoted(dir.path("g.png")) +
                              " --size 96x64 --json " + args);
    };
    {
        const test::CommandResult r = render("");
        ASSERT_EQ(r.exit_code, 0) << r.output;
        const nlohmann::json j = nlohmann::json::parse(r.output);
        EXPECT_EQ(j["frame"], "ellipsoid");
        // The default camera is far out, the whole Earth in view (a sphere of 6,378 km fits
        // a 60° field from a / sin 30° = 12,756 km of the centre), looking straight down.
        const double d =
            std::hypot(double(j["camera"][0]), double(j["camera"][1]), double(j["camera"][2]));
        EXPECT_GT(d, 1.2756e7);
        EXPECT_LT(d, 2.0e7);
        EXPECT_NEAR(double(j["pitch_deg"]), -90.0, 1.0);
    }
    EXPECT_EQ(nlohmann::json::parse(render("--frame plane").output)["frame"], "plane");
    for (const std::string camera :
         {"--camera-lonlat 0,45,-1000 --look-at-lonlat 10,45",         // below the ellipsoid
          "--camera-lonlat 0,90,-6356752.314245 --look-at-lonlat 0,0", // the Earth's centre
          "--camera-lonlat 179.9,-89.9,500 --heading 45 --pitch -10"}) {
        const test::CommandResult r = render(camera);
        ASSERT_EQ(r.exit_code, 0) << camera << ": " << r.output;
        EXPECT_EQ(r.output.find("nan"), std::string::npos) << camera << ": " << r.output;
        EXPECT_EQ(r.output.find("null"), std::string::npos) << camera << ": " << r.output;
    }
    const test::CommandResult bad = render("--frame globe");
    EXPECT_EQ(bad.exit_code, 2) << bad.output;
    EXPECT_NE(bad.output.find("--frame"), std::string::npos) << bad.output;
    // A projected archive lies on the ellipsoid in its place: a camera given in WGS 84 is
    // reported in ECEF where geodetic → ECEF puts it, looking at the summit.
    const std::string utm = dir.path("utm.ridge");
    ASSERT_EQ(test::runRidge("build " + quoted(test::dataPath("everest_utm45.tif")) + " -o " +
                             quoted(utm) + " -q")
                  .exit_code,
              0);
    const test::CommandResult projected = test::runRidge(
        "render " + quoted(utm) + " -o " + quoted(dir.path("u.png")) +
        " --frame ellipsoid --camera-lonlat 86.85,27.85,12000 --look-at-lonlat 86.925,27.988 "
        "--size 96x64 --json");
    ASSERT_EQ(projected.exit_code, 0) << projected.output;
    const nlohmann::json pj = nlohmann::json::parse(projected.output);
    EXPECT_EQ(pj["frame"], "ellipsoid");
    const double a = 6378137.0, e2 = 0.00669437999014, lon = 86.85 * M_PI / 180.0,
                 lat = 27.85 * M_PI / 180.0;
    const double n = a / std::sqrt(1.0 - e2 * std::sin(lat) * std::sin(lat));
    EXPECT_NEAR(double(pj["camera"][0]), (n + 12000.0) * std::cos(lat) * std::cos(lon), 1.0);
    EXPECT_NEAR(double(pj["camera"][1]), (n + 12000.0) * std::cos(lat) * std::sin(lon), 1.0);
    EXPECT_NEAR(double(pj["camera"][2]), (n * (1.0 - e2) + 12000.0) * std::sin(lat), 1.0);
    EXPECT_TRUE(std::filesystem::exists(dir.path("u.png")));
}
