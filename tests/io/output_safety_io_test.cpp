// GDAL's writers through AtomicOutput's "/proc/self/fd/N" (both the unnamed temporary and
// the named fallback), and datasetFiles: every file GDAL reads for a dataset.
#include "io_test_support.h"
#include "test_support.h"

#include "ridge/io/dataset_files.h"
#include "ridge/io/raster_writer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace ridge::io {
namespace {

using test::namesIn;
using test::readFile;

namespace fs = std::filesystem;
using test::ScratchDir;

class NamedTemporaries {
  public:
    explicit NamedTemporaries(bool on)
    {
        if (on)
            ::setenv("RIDGE_TEST_NAMED_TEMPORARIES", "1", 1);
    }
    ~NamedTemporaries() { ::unsetenv("RIDGE_TEST_NAMED_TEMPORARIES"); }
};

class WriterThroughTheMagicLink : public ::testing::TestWithParam<bool> {};

// GTiff (GDALCreate + GDALRasterIO, several tiles and a georeference) and PNG
// (GDALCreateCopy) write their whole file through the descriptor's magic link; a symlink at
// the final path is replaced, its target untouched; nothing else appears in the directory.
TEST_P(WriterThroughTheMagicLink, GeoTiffAndPngAreWrittenWholeAndReplaceASymlinkedFinalPath)
{
    ScratchDir dir, elsewhere;
    NamedTemporaries mode(GetParam());
    const std::string victim = elsewhere.path("victim");
    std::ofstream(victim) << "precious";
    const int w = 700, h = 530;
    std::vector<float> metres(size_t(w) * h);
    for (size_t i = 0; i < metres.size(); ++i)
        metres[i] = float((i * 7919) % 4001) * 0.25f;
    GeoReference geo;
    geo.has_geotransform = true;
    geo.geotransform = {500000, 30, 0, 4000000, 0, -30};
    const std::string tif = dir.path("out.tif");
    fs::create_symlink(victim, tif);
    writeGeoTiff(tif, metres.data(), w, h, geo);
    const test::GdalBand back = test::readWithGdal(tif);
    ASSERT_EQ(back.width, w);
    ASSERT_EQ(back.height, h);
    for (size_t i = 0; i < metres.size(); ++i)
        ASSERT_EQ(back.values[i], double(metres[i])) << i;
    EXPECT_EQ(back.geotransform, geo.geotransform);

    std::vector<uint8_t> rgb(size_t(w) * h * 3);
    for (size_t i = 0; i < rgb.size(); ++i)
        rgb[i] = uint8_t(i * 13);
    const std::string png = dir.path("out.png");
    fs::create_symlink(victim, png);
    writePng(png, rgb.data(), w, h, 3);
    GDALDatasetH ds = GDALOpen(png.c_str(), GA_ReadOnly);
    ASSERT_NE(ds, nullptr);
    std::vector<uint8_t> pixels(rgb.size());
    ASSERT_EQ(GDALDatasetRasterIO(ds, GF_Read, 0, 0, w, h, pixels.data(), w, h, GDT_Byte, 3,
                                  nullptr, 3, w * 3, 1),
              CE_None);
    GDALClose(ds);
    EXPECT_EQ(pixels, rgb);

    EXPECT_EQ(readFile(victim), "precious");
    EXPECT_TRUE(fs::is_regular_file(fs::symlink_status(tif)));
    EXPECT_TRUE(fs::is_regular_file(fs::symlink_status(png)));
    EXPECT_EQ(namesIn(dir.dir()), (std::vector<std::string>{"out.png", "out.tif"}));
}

INSTANTIATE_TEST_SUITE_P(Modes, WriterThroughTheMagicLink, ::testing::Values(false, true),
                         [](const auto& info) { return info.param ? "Named" : "Unnamed"; });

TEST(DatasetFiles, ListsTheHeaderOfAnEnviRasterAndTheAuxXmlOfAGeoTiff)
{
    ScratchDir dir;
    GDALAllRegister();
    GDALDatasetH src = GDALOpen(test::dataPath("everest_crop.tif").c_str(), GA_ReadOnly);
    ASSERT_NE(src, nullptr);
    const std::string bil = dir.path("d.bil");
    GDALDatasetH envi = GDALCreateCopy(GDALGetDriverByName("ENVI"), bil.c_str(), src, FALSE,
                                       nullptr, nullptr, nullptr);
    ASSERT_NE(envi, nullptr);
    GDALClose(envi);
    const std::string tif = dir.path("d.tif");
    GDALClose(GDALCreateCopy(GDALGetDriverByName("GTiff"), tif.c_str(), src, FALSE, nullptr,
                             nullptr, nullptr));
    GDALClose(src);
    std::ofstream(tif + ".aux.xml")
        << "<PAMDataset><Metadata><MDI key=\"k\">v</MDI></Metadata></PAMDataset>\n";

    const std::vector<std::string> envi_files = datasetFiles(bil);
    ASSERT_FALSE(envi_files.empty());
    EXPECT_EQ(envi_files.front(), bil);
    EXPECT_NE(std::find(envi_files.begin(), envi_files.end(), dir.path("d.hdr")), envi_files.end());
    const std::vector<std::string> tif_files = datasetFiles(tif);
    EXPECT_NE(std::find(tif_files.begin(), tif_files.end(), tif + ".aux.xml"), tif_files.end());
}

TEST(DatasetFiles, IsJustThePathWhenGdalCannotOpenIt)
{
    ScratchDir dir;
    EXPECT_EQ(datasetFiles(dir.path("missing.tif")),
              std::vector<std::string>{dir.path("missing.tif")});
    std::ofstream(dir.path("garbage.tif")) << "not a raster";
    EXPECT_EQ(datasetFiles(dir.path("garbage.tif")),
              std::vector<std::string>{dir.path("garbage.tif")});
}

} // namespace
} // namespace ridge::io
