// `ridge view` as a user runs it: a few frames in a virtual X server (Xvfb, Mesa llvmpipe
// through GLX gives GL 4.5), and a clear refusal without a display.
#include "test_support.h"

#include <gdal.h>
#include <gtest/gtest.h>

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
