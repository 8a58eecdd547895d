// `ridge view` as a user runs it: a few frames in a virtual X server (Xvfb, Mesa llvmpipe
// through GLX gives GL 4.5), and a clear refusal without a display.
#include "test_support.h"

#include <gdal.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <set>
#include <string>
#include <sys/wait.h>
#include <vector>

using namespace ridge;

namespace {

bool haveXvfbRun()
{
    return std::system("command -v xvfb-run > /dev/null 2>&1") == 0;
}

std::string buildArchive(const test::ScratchDir& dir)
{
    return test::buildEverestWithCli(dir, "everest.ridge", "");
}

} // namespace

TEST(ViewSmoke, RendersFramesInAVirtualDisplayAndExits)
{
    if (!haveXvfbRun())
        GTEST_SKIP()
            << "xvfb-run is not installed (apt-get install xvfb): cannot open a window here";
    test::ScratchDir dir;
    const std::string arc = buildArchive(dir);
    const std::string png = dir.path("last-frame.png");
    const test::CommandResult r =
        test::runShell("xvfb-run -a -s '-screen 0 1280x1024x24' " + std::string(RIDGE_CLI_PATH) +
                       " view '" + arc + "' --frames 5 --size 640x360 --screenshot '" + png + "'");
    ASSERT_EQ(r.exit_code, 0) << r.output;

    // The last frame came back from the default framebuffer at the window's size, with more
    // than a flat clear colour in it: terrain and overlay.
    GDALAllRegister();
    GDALDatasetH ds = GDALOpen(png.c_str(), GA_ReadOnly);
    ASSERT_NE(ds, nullptr) << r.output;
    const int w = GDALGetRasterXSize(ds), h = GDALGetRasterYSize(ds);
    EXPECT_EQ(w, 640);
    EXPECT_EQ(h, 360);
    ASSERT_EQ(GDALGetRasterCount(ds), 3);
    std::vector<uint8_t> rgb(size_t(w) * h * 3);
    ASSERT_EQ(GDALDatasetRasterIO(ds, GF_Read, 0, 0, w, h, rgb.data(), w, h, GDT_Byte, 3, nullptr,
                                  3, w * 3, 1),
              CE_None);
    GDALClose(ds);
    std::set<uint32_t> colours;
    for (size_t i = 0; i < rgb.size(); i += 3)
        colours.insert(uint32_t(rgb[i]) << 16 | uint32_t(rgb[i + 1]) << 8 | rgb[i + 2]);
    EXPECT_GT(colours.size(), 200u) << "looks like an empty frame";
}

TEST(ViewSmoke, WithoutADisplayItFailsAndSaysWhy)
{
    test::ScratchDir dir;
    const std::string arc = buildArchive(dir);
    const std::string cli = "env -u DISPLAY -u WAYLAND_DISPLAY " + std::string(RIDGE_CLI_PATH);
    test::CommandResult r = test::runShell(cli + " view '" + arc + "' --frames 1");
    EXPECT_NE(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("no display"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("DISPLAY"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("ridge render"), std::string::npos)
        << "should point to the alternative: " << r.output;
    EXPECT_EQ(r.output.find("Segmentation"), std::string::npos);

    r = test::runShell(cli + " view '" + arc + "' --size 640by360");
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.output.find("--size 640by360"), std::string::npos) << r.output;
}

TEST(ViewSmoke, StartsAtAGeographicCameraAndRefusesABadOneBeforeOpeningAWindow)
{
    if (!haveXvfbRun())
        GTEST_SKIP()
            << "xvfb-run is not installed (apt-get install xvfb): cannot open a window here";
    test::ScratchDir dir;
    const std::string arc = buildArchive(dir);
    const std::string xvfb =
        "xvfb-run -a -s '-screen 0 1280x1024x24' " + std::string(RIDGE_CLI_PATH) + " view '" + arc;
    const test::CommandResult ok = test::runShell(
        xvfb + "' --frames 2 --size 320x180 --camera-lonlat 86.925,27.988,9500 --heading 200 "
               "--pitch -20");
    EXPECT_EQ(ok.exit_code, 0) << ok.output;
    const test::CommandResult bad = test::runShell(
        xvfb + "' --frames 2 --size 320x180 --camera-lonlat 86.925,95,9500 --heading 200 "
               "--pitch -20");
    EXPECT_EQ(bad.exit_code, 1) << bad.output;
    EXPECT_NE(bad.output.find("latitude"), std::string::npos) << bad.output;
}

namespace {

struct Picture {
    int width = 0, height = 0;
    std::vector<uint8_t> rgb;
};

Picture readPicture(const std::string& path)
{
    GDALAllRegister();
    Picture p;
    GDALDatasetH ds = GDALOpen(path.c_str(), GA_ReadOnly);
    EXPECT_NE(ds, nullptr) << path;
    if (!ds)
        return p;
    p.width = GDALGetRasterXSize(ds);
    p.height = GDALGetRasterYSize(ds);
    p.rgb.resize(size_t(p.width) * p.height * 3);
    EXPECT_EQ(GDALDatasetRasterIO(ds, GF_Read, 0, 0, p.width, p.height, p.rgb.data(), p.width,
                                  p.height, GDT_Byte, 3, nullptr, 3, p.width * 3, 1),
              CE_None);
    GDALClose(ds);
    return p;
}

// `ridge view ARCHIVE ARGS` for a few frames in Xvfb, patches loaded before each frame (no
// streaming: two runs draw the same terrain), the last frame as `png`.
test::CommandResult viewShot(const std::string& archive, const std::string& png,
                             const std::string& args)
{
    return test::runShell("xvfb-run -a -s '-screen 0 1400x900x24' " + std::string(RIDGE_CLI_PATH) +
                          " view '" + archive + "' --frames 6 --size 1280x720 --no-streaming " +
                          "--screenshot '" + png + "' " + args);
}

} // namespace

// The overlay covered about 70 % x 55 % of a 1280 x 720 window, hiding the summit the camera
// looks at. Measured as the pixels that differ between the same view with and without it.
TEST(ViewSmoke, TheOverlayIsCompact)
{
    if (!haveXvfbRun())
        GTEST_SKIP() << "xvfb-run is not installed (apt-get install xvfb)";
    test::ScratchDir dir;
    const std::string arc = buildArchive(dir);
    const std::string with = dir.path("with.png"), without = dir.path("without.png");
    test::CommandResult r = viewShot(arc, with, "");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    r = viewShot(arc, without, "--no-overlay");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const Picture a = readPicture(with), b = readPicture(without);
    ASSERT_EQ(a.width, 1280);
    ASSERT_EQ(a.height, 720);
    ASSERT_EQ(a.rgb.size(), b.rgb.size());
    int x0 = a.width, x1 = -1, y0 = a.height, y1 = -1;
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x) {
            const size_t i = (size_t(y) * a.width + x) * 3;
            if (a.rgb[i] != b.rgb[i] || a.rgb[i + 1] != b.rgb[i + 1] ||
                a.rgb[i + 2] != b.rgb[i + 2]) {
                x0 = std::min(x0, x);
                x1 = std::max(x1, x);
                y0 = std::min(y0, y);
                y1 = std::max(y1, y);
            }
        }
    ASSERT_GE(x1, 0) << "no overlay drawn at all";
    const double w = double(x1 - x0 + 1) / a.width, h = double(y1 - y0 + 1) / a.height;
    EXPECT_LE(w, 0.32) << "overlay " << x0 << ".." << x1 << " x " << y0 << ".." << y1;
    EXPECT_LE(h, 0.32) << "overlay " << x0 << ".." << x1 << " x " << y0 << ".." << y1;
    EXPECT_LE(w * h, 0.10);
    // In the top-left corner, clear of the centre, where the default view puts the terrain.
    EXPECT_LT(x1, a.width / 2);
    EXPECT_LT(y1, a.height / 2);
}

// `view --mode` as `render --mode`: it was refused as an unknown option.
TEST(ViewSmoke, TakesTheModeRenderTakes)
{
    test::ScratchDir dir;
    const std::string arc = buildArchive(dir);
    // Without a display: refused for the display (status 1), not for the flag (status 2).
    const std::string cli = "env -u DISPLAY -u WAYLAND_DISPLAY " + std::string(RIDGE_CLI_PATH);
    test::CommandResult r = test::runShell(cli + " view '" + arc + "' --mode lod --frames 1");
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_NE(r.output.find("no display"), std::string::npos) << r.output;
    r = test::runShell(cli + " view '" + arc + "' --mode heat --frames 1");
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("--mode heat: expected shaded, lod or tess"), std::string::npos)
        << r.output;
    if (!haveXvfbRun())
        GTEST_SKIP() << "xvfb-run is not installed (apt-get install xvfb)";
    // Drawn: the level colours differ from the shading over the terrain.
    const std::string shaded = dir.path("shaded.png"), lod = dir.path("lod.png");
    ASSERT_EQ(viewShot(arc, shaded, "--no-overlay").exit_code, 0);
    r = viewShot(arc, lod, "--no-overlay --mode lod");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const Picture a = readPicture(shaded), b = readPicture(lod);
    ASSERT_EQ(a.rgb.size(), b.rgb.size());
    size_t differ = 0;
    for (size_t i = 0; i < a.rgb.size(); i += 3)
        differ +=
            a.rgb[i] != b.rgb[i] || a.rgb[i + 1] != b.rgb[i + 1] || a.rgb[i + 2] != b.rgb[i + 2];
    EXPECT_GT(differ, a.rgb.size() / 3 / 5) << "the LOD colours should cover the terrain";
}

// The globe in the viewer: a raster that goes round the Earth opens on the ellipsoid (auto,
// as in `ridge render`), from the default camera that frames the whole Earth, and from a
// geographic camera low over the ground; --frame plane still flattens it.
TEST(ViewSmoke, FliesTheGlobeOnTheEllipsoid)
{
    if (!haveXvfbRun())
        GTEST_SKIP()
            << "xvfb-run is not installed (apt-get install xvfb): cannot open a window here";
    test::ScratchDir dir;
    const std::string arc =
        test::buildWithCli(dir, "etopo5_globe_181x91.tif", "globe.ridge", "--patch 17");
    const std::string orbit = dir.path("orbit.png");
    test::CommandResult r = viewShot(arc, orbit, "--no-overlay");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    // The whole Earth in the middle of the window, space (black) in its corners.
    const Picture p = readPicture(orbit);
    ASSERT_EQ(p.width, 1280);
    auto rgbAt = [&](int x, int y) {
        const uint8_t* c = &p.rgb[(size_t(y) * p.width + x) * 3];
        return int(c[0]) + int(c[1]) + int(c[2]);
    };
    EXPECT_GT(rgbAt(640, 360), 60) << "the globe at the centre";
    EXPECT_LT(rgbAt(5, 5), 30) << "space in the corner";

    // Low over the Himalaya looking north: ground below the horizon, sky above.
    const std::string low = dir.path("low.png");
    r = viewShot(arc, low, "--no-overlay --camera-lonlat 86,26,3000 --heading 0 --pitch -5");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const Picture q = readPicture(low);
    ASSERT_EQ(q.width, 1280);
    const uint8_t* sky = &q.rgb[(size_t(20) * q.width + 640) * 3];
    const uint8_t* ground = &q.rgb[(size_t(700) * q.width + 640) * 3];
    EXPECT_GT(int(sky[2]), int(sky[0]) + 30) << "blue sky at the top";
    const int sky_minus_ground =
        std::abs(sky[0] - ground[0]) + std::abs(sky[1] - ground[1]) + std::abs(sky[2] - ground[2]);
    EXPECT_GT(sky_minus_ground, 30) << "terrain at the bottom";

    // Orbiting (--orbit, M in the window): the orbit camera starts on the view it was given
    // (an oblique look at the Himalaya from 2,000 km: the fly camera's picture, pixel for
    // pixel up to rounding).
    const std::string given = "--no-overlay --camera-lonlat 80,20,2000000 --look-at-lonlat 87,30";
    const std::string flying = dir.path("flying.png"), orbiting = dir.path("orbiting.png");
    ASSERT_EQ(viewShot(arc, flying, given).exit_code, 0);
    r = viewShot(arc, orbiting, given + " --orbit");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const Picture f = readPicture(flying), o = readPicture(orbiting);
    ASSERT_EQ(o.rgb.size(), f.rgb.size());
    size_t same = 0;
    for (size_t i = 0; i + 2 < o.rgb.size(); i += 3)
        same += std::abs(int(o.rgb[i]) - int(f.rgb[i])) +
                    std::abs(int(o.rgb[i + 1]) - int(f.rgb[i + 1])) +
                    std::abs(int(o.rgb[i + 2]) - int(f.rgb[i + 2])) <
                12;
    EXPECT_GT(same, o.rgb.size() / 3 * 97 / 100) << "the orbit starts on the view it was given";
    // Off a globe there is nothing to orbit.
    const std::string plane = test::buildEverestWithCli(dir, "plane.ridge", "");
    r = viewShot(plane, dir.path("plane.png"), "--orbit");
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("--orbit"), std::string::npos) << r.output;
}
