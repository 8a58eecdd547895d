// `ridge extract` as gdal_translate's user expects it: the source's type by default, -ot, -of,
// -co, -a_nodata, --srcwin and --projwin, and every bad value refused with nothing left behind.
#include "gdal_translate.h"
#include "test_support.h"

#include <gdal.h>
#include <gdal_utils.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <array>
#include <cmath>
#include <filesystem>
#include <vector>

using namespace ridge;
namespace fs = std::filesystem;

namespace {

using test::gdalTranslate;

std::string inQuotes(const std::string& path)
{
    return "'" + path + "'";
}

struct Raster {
    int width = 0, height = 0;
    GDALDataType type = GDT_Unknown;
    std::array<double, 6> gt{};
    bool has_gt = false;
    std::optional<double> nodata;
    std::vector<double> values;
};

Raster readRaster(const std::string& path)
{
    GDALAllRegister();
    Raster r;
    GDALDatasetH ds = GDALOpen(path.c_str(), GA_ReadOnly);
    EXPECT_NE(ds, nullptr) << path;
    if (!ds)
        return r;
    r.width = GDALGetRasterXSize(ds);
    r.height = GDALGetRasterYSize(ds);
    GDALRasterBandH band = GDALGetRasterBand(ds, 1);
    r.type = GDALGetRasterDataType(band);
    r.has_gt = GDALGetGeoTransform(ds, r.gt.data()) == CE_None;
    int has_nodata = 0;
    const double nodata = GDALGetRasterNoDataValue(band, &has_nodata);
    if (has_nodata)
        r.nodata = nodata;
    r.values.resize(size_t(r.width) * r.height);
    EXPECT_EQ(GDALRasterIO(band, GF_Read, 0, 0, r.width, r.height, r.values.data(), r.width,
                           r.height, GDT_Float64, 0, 0),
              CE_None);
    GDALClose(ds);
    return r;
}

class ExtractCli : public ::testing::Test {
  protected:
    static void SetUpTestSuite()
    {
        scratch_ = new test::ScratchDir();
        lossless_ = new std::string(test::buildEverestWithCli(*scratch_, "lossless.ridge", ""));
        // Heights of 0.3048 m a code (feet): no longer integers.
        feet_ = new std::string(
            test::buildEverestWithCli(*scratch_, "feet.ridge", "--patch 65 --z-scale 0.3048"));
    }
    static void TearDownTestSuite()
    {
        delete feet_;
        delete lossless_;
        delete scratch_;
    }
    static std::string path(const std::string& name) { return scratch_->path(name); }

    // `ridge extract ARCHIVE -o out.NAME ARGS` exits with `status`, says each phrase, and
    // leaves no out.* (nor a temporary) behind.
    static void expectRefused(const std::string& args, int status,
                              const std::vector<std::string>& phrases)
    {
        const test::CommandResult r =
            test::runRidge("extract " + inQuotes(*lossless_) + " -q " + args);
        SCOPED_TRACE(args);
        EXPECT_EQ(r.exit_code, status) << r.output;
        for (const std::string& p : phrases)
            EXPECT_NE(r.output.find(p), std::string::npos)
                << "expected '" << p << "' in: " << r.output;
        for (const auto& entry : fs::directory_iterator(scratch_->dir()))
            EXPECT_NE(entry.path().filename().string().rfind("out.", 0), 0u)
                << "left behind: " << entry.path();
        EXPECT_EQ(test::temporariesIn(scratch_->dir()), std::vector<std::string>{});
    }

    static test::ScratchDir* scratch_;
    static std::string* lossless_;
    static std::string* feet_;
};

test::ScratchDir* ExtractCli::scratch_ = nullptr;
std::string* ExtractCli::lossless_ = nullptr;
std::string* ExtractCli::feet_ = nullptr;

} // namespace

TEST_F(ExtractCli, AnInt16SourceComesBackAsInt16SampleForSample)
{
    const std::string src = test::dataPath("everest_crop.tif");
    for (const std::string& args : {std::string(), std::string("-ot Int16")}) {
        const std::string out = path("int16.tif");
        const test::CommandResult r = test::runRidgeStdout(
            "extract " + inQuotes(*lossless_) + " -o " + inQuotes(out) + " --json " + args);
        ASSERT_EQ(r.exit_code, 0) << r.output;
        const nlohmann::json j = nlohmann::json::parse(r.output);
        EXPECT_EQ(j["type"], "Int16");
        EXPECT_EQ(j["type_reason"], args.empty() ? "the source's type" : "requested");
        EXPECT_EQ(j["max_rounding_error"].get<double>(), 0.0);
        const Raster a = readRaster(src), b = readRaster(out);
        EXPECT_EQ(b.type, GDT_Int16) << args;
        EXPECT_EQ(b.width, a.width);
        EXPECT_EQ(b.height, a.height);
        EXPECT_EQ(b.values, a.values) << args;
        EXPECT_EQ(b.gt, a.gt);
        // Float32, as extract always wrote before, only when asked.
        const std::string f32 = path("float32.tif");
        ASSERT_EQ(test::runRidge("extract " + inQuotes(*lossless_) + " -o " + inQuotes(f32) +
                                 " -q -ot Float32")
                      .exit_code,
                  0);
        EXPECT_EQ(readRaster(f32).type, GDT_Float32);
        EXPECT_EQ(readRaster(f32).values, a.values);
    }
}

TEST_F(ExtractCli, NonIntegerHeightsFallBackToFloat32UnlessAnIntegerTypeIsAsked)
{
    const std::string out = path("feet.tif");
    test::CommandResult r =
        test::runRidgeStdout("extract " + inQuotes(*feet_) + " -o " + inQuotes(out) + " --json");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    nlohmann::json j = nlohmann::json::parse(r.output);
    EXPECT_EQ(j["type"], "Float32");
    EXPECT_NE(j["type_reason"].get<std::string>().find("the source's Int16 cannot hold"),
              std::string::npos)
        << j.dump();
    const Raster source = readRaster(test::dataPath("everest_crop.tif"));
    const Raster f = readRaster(out);
    EXPECT_EQ(f.type, GDT_Float32);
    ASSERT_EQ(f.values.size(), source.values.size());
    for (size_t i = 0; i < f.values.size(); ++i)
        ASSERT_NEAR(f.values[i], source.values[i] * 0.3048, 1e-3) << i;
    // Asked for Int16: rounded to whole metres, and said by how much.
    r = test::runRidgeStdout("extract " + inQuotes(*feet_) + " -o " + inQuotes(out) +
                             " --json -ot Int16");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    j = nlohmann::json::parse(r.output);
    EXPECT_EQ(j["type"], "Int16");
    EXPECT_EQ(j["type_reason"], "requested");
    EXPECT_GT(j["max_rounding_error"].get<double>(), 0.4);
    EXPECT_LE(j["max_rounding_error"].get<double>(), 0.5);
    const Raster i16 = readRaster(out);
    EXPECT_EQ(i16.type, GDT_Int16);
    EXPECT_EQ(i16.values[0], std::round(source.values[0] * 0.3048));
}

// The same window as gdal_translate -projwin on the source: same size, georeferencing and
// samples (the lossless archive holds the source exactly).
TEST_F(ExtractCli, ProjwinMatchesGdalTranslate)
{
    const std::string src = test::dataPath("everest_crop.tif");
    for (const std::vector<std::string>& corners :
         {std::vector<std::string>{"86.8", "27.95", "86.85", "27.9"},
          std::vector<std::string>{"86.7601", "27.99", "86.9012", "27.85"},
          std::vector<std::string>{"86.75", "28.0", "87.0", "27.8325"}}) {
        std::string ours_args, joined;
        for (const std::string& c : corners)
            joined += " " + c;
        const std::string ours = path("projwin.tif"), theirs = path("projwin_gdal.tif");
        const test::CommandResult r = test::runRidge("extract " + inQuotes(*lossless_) + " -o " +
                                                     inQuotes(ours) + " -q --projwin" + joined);
        ASSERT_EQ(r.exit_code, 0) << joined << ": " << r.output;
        gdalTranslate(src, theirs, {"-projwin", corners[0], corners[1], corners[2], corners[3]});
        const Raster a = readRaster(theirs), b = readRaster(ours);
        SCOPED_TRACE(joined);
        EXPECT_EQ(b.width, a.width);
        EXPECT_EQ(b.height, a.height);
        for (int k = 0; k < 6; ++k)
            EXPECT_DOUBLE_EQ(b.gt[k], a.gt[k]) << k;
        EXPECT_EQ(b.values, a.values);
        EXPECT_EQ(b.type, a.type);
    }
    // At a coarser level the window is cut from that level's grid: pixels of the level's
    // size, the first one's centre inside the window.
    const std::string coarse = path("coarse.tif");
    ASSERT_EQ(test::runRidge("extract " + inQuotes(*lossless_) + " -o " + inQuotes(coarse) +
                             " -q --level 1 --projwin 86.8 27.95 86.85 27.9")
                  .exit_code,
              0);
    const Raster c = readRaster(coarse), s = readRaster(src);
    EXPECT_DOUBLE_EQ(c.gt[1], 2 * s.gt[1]);
    EXPECT_GE(c.gt[0] + 0.5 * c.gt[1], 86.8 - 1e-9);
    EXPECT_LE(c.gt[3] + 0.5 * c.gt[5], 27.95 + 1e-9);
}

TEST_F(ExtractCli, SrcwinIsGdalTranslatesSrcwin)
{
    const std::string ours = path("srcwin.tif"), theirs = path("srcwin_gdal.tif");
    ASSERT_EQ(test::runRidge("extract " + inQuotes(*lossless_) + " -o " + inQuotes(ours) +
                             " -q --srcwin 17 23 101 77")
                  .exit_code,
              0);
    gdalTranslate(test::dataPath("everest_crop.tif"), theirs, {"-srcwin", "17", "23", "101", "77"});
    const Raster a = readRaster(theirs), b = readRaster(ours);
    EXPECT_EQ(b.width, 101);
    EXPECT_EQ(b.values, a.values);
    EXPECT_EQ(b.gt, a.gt);
}

TEST_F(ExtractCli, OtherFormatsCreationOptionsAndNodata)
{
    // PNG holds UInt16; its georeference goes into the .aux.xml side-car, published with it.
    const std::string png = path("heights.png");
    test::CommandResult r = test::runRidge("extract " + inQuotes(*lossless_) + " -o " +
                                           inQuotes(png) + " -q -of PNG -ot UInt16 -co ZLEVEL=1");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_TRUE(fs::exists(png + ".aux.xml"));
    const Raster source = readRaster(test::dataPath("everest_crop.tif"));
    Raster p = readRaster(png);
    EXPECT_EQ(p.type, GDT_UInt16);
    EXPECT_EQ(p.values, source.values);
    EXPECT_TRUE(p.has_gt);
    EXPECT_EQ(p.gt, source.gt);
    // The creation option reaches the driver: ZLEVEL=9 compresses better than ZLEVEL=1.
    const std::string png9 = path("heights9.png");
    ASSERT_EQ(test::runRidge("extract " + inQuotes(*lossless_) + " -o " + inQuotes(png9) +
                             " -q -of PNG -ot UInt16 -co ZLEVEL=9")
                  .exit_code,
              0);
    EXPECT_LT(fs::file_size(png9), fs::file_size(png));
    // An ASCII grid (CreateCopy only), with a nodata value.
    const std::string asc = path("heights.asc");
    r = test::runRidge("extract " + inQuotes(*lossless_) + " -o " + inQuotes(asc) +
                       " -q -of AAIGrid --srcwin 0 0 20 10 -a_nodata -9999");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const Raster a = readRaster(asc);
    EXPECT_EQ(a.width, 20);
    ASSERT_TRUE(a.nodata);
    EXPECT_EQ(*a.nodata, -9999);
    EXPECT_EQ(a.values[0], source.values[0]);
    // A GTiff creation option overrides the default (DEFLATE): LZW shows in the metadata.
    const std::string lzw = path("lzw.tif");
    ASSERT_EQ(test::runRidge("extract " + inQuotes(*lossless_) + " -o " + inQuotes(lzw) +
                             " -q -co COMPRESS=LZW")
                  .exit_code,
              0);
    GDALDatasetH ds = GDALOpen(lzw.c_str(), GA_ReadOnly);
    ASSERT_NE(ds, nullptr);
    EXPECT_STREQ(GDALGetMetadataItem(ds, "COMPRESSION", "IMAGE_STRUCTURE"), "LZW");
    GDALClose(ds);
}

// Usage errors (the value cannot be right for its flag) exit 2; values the archive, the type or
// GDAL cannot take exit 1. Nothing is left behind either way.
TEST_F(ExtractCli, BadValuesAreRefusedWithTheDocumentedStatus)
{
    const std::string out = " -o " + inQuotes(path("out.tif"));
    expectRefused(out + " -ot Int8", 2,
                  {"--ot Int8: not a type ridge writes; did you mean 'Int16'?"});
    expectRefused(out + " -co COMPRESS", 2, {"--co COMPRESS: expected NAME=VALUE"});
    expectRefused(out + " --projwin 86.8 nan 86.85 27.9", 2, {"--projwin nan:"});
    expectRefused(out + " --srcwin 0 0 0 10", 2, {"--srcwin 0: XSIZE must be an integer"});
    expectRefused(out + " --srcwin 1 2 3 4 --projwin 86.8 27.95 86.85 27.9", 2,
                  {"--srcwin excludes --projwin"});
    expectRefused(out + " --a_nodata inf", 2, {"--a_nodata inf:"});
    expectRefused(out + " -ot", 2, {"--ot"});
    expectRefused(out + " --srcwin 250 0 100 10", 1,
                  {"window (250 0 100 10) reaches outside level", "301 x 203 samples"});
    expectRefused(out + " --projwin 86.8 27.95 87.5 27.9", 1,
                  {"projwin 86.8 27.95 87.5 27.9 (samples 60 60 840 60) reaches outside"});
    expectRefused(out + " --projwin 86.8 27.95 86.8 27.9", 1, {"the window is empty"});
    expectRefused(out + " --projwin 86.85 27.9 86.8 27.95", 1, {"selects no whole pixel"});
    expectRefused(out + " -of GTIF", 1,
                  {"output_format 'GTIF': no such GDAL driver; did you "
                   "mean 'GTiff'?"});
    expectRefused(out + " -of MEM", 1, {"output_format 'MEM'", "cannot write"});
    expectRefused(" -o " + inQuotes(path("out.png")) + " -of PNG -co BOGUS=1", 1,
                  {"driver PNG does not support creation option BOGUS", "creation_options is -co"});
    expectRefused(" -o " + inQuotes(path("out.png")) + " -of PNG", 1,
                  {"PNG driver doesn't support data type Int16"});
    expectRefused(out + " -ot Byte", 1,
                  {"output_type Byte cannot hold the window's heights "
                   "[3369, 8840] m"});
    expectRefused(out + " -a_nodata 100000", 1, {"nodata_value", "Int16 cannot hold it"});
    expectRefused(out + " --srcwin 0 0 1 1 -a_nodata 5552", 1,
                  {"nodata_value 5552 is the height of 1 extracted samples"});
    expectRefused(" -o " + inQuotes(*lossless_), 1, {"refusing to replace an input"});
}
