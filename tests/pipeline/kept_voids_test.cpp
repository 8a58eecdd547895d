// Voids kept as holes (io::VoidFill): the empty collar of a DEM warped to UTM is not terrain,
// holes enclosed by data are. End to end on real fixtures: ingest -> build -> validity masks
// -> extract / verify / hillshade read back through GDAL, compared with the source itself.
#include "test_support.h"

#include "ridge/archive/archive_reader.h"
#include "ridge/core/error.h"
#include "ridge/io/raster_source.h"
#include "ridge/pipeline/build.h"
#include "ridge/pipeline/extract.h"
#include "ridge/pipeline/hillshade.h"
#include "ridge/pipeline/level_decoder.h"
#include "ridge/pipeline/verify.h"

#include <gdal.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <vector>

using namespace ridge;

namespace {

// The source in metres, NaN at voids (the reference verify uses).
struct Source {
    int width = 0, height = 0;
    std::vector<double> metres;
    bool isVoid(int x, int y) const { return std::isnan(metres[size_t(y) * width + x]); }
};

Source readSource(const std::string& path)
{
    io::ReferenceRaster r(path, io::IngestOptions{});
    Source s{r.width(), r.height(), std::vector<double>(size_t(r.width()) * r.height())};
    r.readRows(0, s.height, s.metres.data());
    return s;
}

// The test's own flood fill (4 + diagonal neighbours), independent of src/io/border_voids.
std::vector<uint8_t> borderConnectedVoids(const Source& s, int64_t& count)
{
    std::vector<uint8_t> out(s.metres.size(), 0);
    std::vector<std::pair<int, int>> todo;
    for (int x = 0; x < s.width; ++x)
        todo.insert(todo.end(), {{x, 0}, {x, s.height - 1}});
    for (int y = 0; y < s.height; ++y)
        todo.insert(todo.end(), {{0, y}, {s.width - 1, y}});
    count = 0;
    while (!todo.empty()) {
        const auto [x, y] = todo.back();
        todo.pop_back();
        if (x < 0 || y < 0 || x >= s.width || y >= s.height || !s.isVoid(x, y) ||
            out[size_t(y) * s.width + x])
            continue;
        out[size_t(y) * s.width + x] = 1;
        ++count;
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx)
                todo.push_back({x + dx, y + dy});
    }
    return out;
}

struct Exported {
    int width = 0, height = 0;
    std::vector<float> values;
    int has_nodata = 0;
    double nodata = 0;
    bool isNodata(size_t i) const
    {
        return has_nodata && (std::isnan(nodata) ? std::isnan(values[i]) : values[i] == nodata);
    }
};

Exported readExport(const std::string& path)
{
    GDALAllRegister();
    GDALDatasetH ds = GDALOpen(path.c_str(), GA_ReadOnly);
    EXPECT_NE(ds, nullptr);
    Exported e;
    if (!ds)
        return e;
    e.width = GDALGetRasterXSize(ds);
    e.height = GDALGetRasterYSize(ds);
    GDALRasterBandH band = GDALGetRasterBand(ds, 1);
    e.nodata = GDALGetRasterNoDataValue(band, &e.has_nodata);
    e.values.resize(size_t(e.width) * e.height);
    EXPECT_EQ(GDALRasterIO(band, GF_Read, 0, 0, e.width, e.height, e.values.data(), e.width,
                           e.height, GDT_Float32, 0, 0),
              CE_None);
    GDALClose(ds);
    return e;
}

BuildOptions options(io::VoidFill mode, int patch = 33)
{
    BuildOptions o;
    o.patch_size = patch;
    o.ingest.fill_voids = mode;
    return o;
}

} // namespace

TEST(KeptVoids, WarpedCollarStaysNodataAndOnlyTheSourceFootprintIsExported)
{
    test::ScratchDir dir;
    const std::string source_path = test::dataPath("everest_utm44.tif");
    const Source source = readSource(source_path);
    int64_t collar = 0;
    const std::vector<uint8_t> outside = borderConnectedVoids(source, collar);
    ASSERT_GT(collar, 5000); // the fixture really has a collar (5679 samples)

    for (const int patch : {17, 33}) {
        const std::string archive_path = dir.path("utm.ridge");
        const BuildReport report =
            buildArchive(source_path, archive_path, options(io::VoidFill::Interior, patch));
        EXPECT_EQ(report.voids_kept, collar);
        EXPECT_EQ(report.voids_filled, 0);
        const archive::ArchiveReader reader(archive_path);
        EXPECT_EQ(reader.header().version, archive::kFormatVersion);
        EXPECT_EQ(reader.metadata().source.voids_kept, collar);
        EXPECT_EQ(reader.metadata().source.fill_voids, "interior");

        const std::string tif = dir.path("finest.tif");
        extractLevel(archive_path, tif, {});
        const Exported e = readExport(tif);
        ASSERT_EQ(e.width, source.width);
        ASSERT_EQ(e.height, source.height);
        ASSERT_TRUE(e.has_nodata);
        EXPECT_EQ(e.nodata, -32768.0); // the source's own nodata value
        const double bound = reader.levelErrorBound(reader.geometry().finestLevel());
        int64_t nodata = 0;
        for (int y = 0; y < e.height; ++y)
            for (int x = 0; x < e.width; ++x) {
                const size_t i = size_t(y) * e.width + x;
                ASSERT_EQ(e.isNodata(i), outside[i] != 0) << "sample " << x << "," << y;
                if (e.isNodata(i)) {
                    ++nodata;
                    continue;
                }
                ASSERT_LE(std::fabs(e.values[i] - source.metres[i]), bound + 1e-3) << x << "," << y;
            }
        EXPECT_EQ(nodata, collar);

        VerifyOptions v;
        v.source = source_path;
        const VerifyReport vr = verifyArchive(archive_path, v);
        ASSERT_TRUE(vr.ok()) << vr.problems.front();
        EXPECT_EQ(vr.nodata_samples, collar);
        EXPECT_EQ(vr.source_voids, collar);
    }
}

TEST(KeptVoids, CoarseLevelsExportTheFinestValidityAtTheirPositions)
{
    test::ScratchDir dir;
    const std::string source_path = test::dataPath("everest_utm44.tif");
    const Source source = readSource(source_path);
    const std::string archive_path = dir.path("utm.ridge");
    buildArchive(source_path, archive_path, options(io::VoidFill::Interior, 17));
    const archive::ArchiveReader reader(archive_path);
    const PyramidGeometry& g = reader.geometry();
    for (int level = 0; level < g.finestLevel(); ++level) {
        std::vector<uint8_t> valid;
        const CodeGrid grid = decodeLevelWindow(reader, level, 0, 0, g.validLevelWidth(level),
                                                g.validLevelHeight(level), {}, &valid);
        const int64_t s = g.step(level);
        int64_t kept = 0;
        for (int j = 0; j < grid.height; ++j)
            for (int i = 0; i < grid.width; ++i) {
                const bool expected = !source.isVoid(int(i * s), int(j * s));
                const bool got = valid.empty() || valid[size_t(j) * grid.width + i];
                ASSERT_EQ(got, expected) << "level " << level << " sample " << i << "," << j;
                kept += !got;
            }
        if (level >= 2) {
            EXPECT_GT(kept, 0) << "level " << level;
        }
    }
}

TEST(KeptVoids, InteriorVoidsAreStillFilledAndNoneKeepsThem)
{
    test::ScratchDir dir;
    const std::string source_path = test::dataPath("rainier_voids.tif");
    const Source source = readSource(source_path);
    int64_t border = 0;
    borderConnectedVoids(source, border);
    ASSERT_EQ(border, 0); // its 368 voids are all interior

    const std::string filled = dir.path("interior.ridge");
    const BuildReport r1 = buildArchive(source_path, filled, options(io::VoidFill::Interior));
    EXPECT_EQ(r1.voids_filled, 368);
    EXPECT_EQ(r1.voids_kept, 0);
    extractLevel(filled, dir.path("interior.tif"), {});
    const Exported e1 = readExport(dir.path("interior.tif"));
    for (size_t i = 0; i < e1.values.size(); ++i)
        ASSERT_FALSE(e1.isNodata(i)) << i;
    EXPECT_FALSE(e1.has_nodata);

    const std::string kept = dir.path("none.ridge");
    const BuildReport r2 = buildArchive(source_path, kept, options(io::VoidFill::None));
    EXPECT_EQ(r2.voids_filled, 0);
    EXPECT_EQ(r2.voids_kept, 368);
    ExtractOptions nan_nodata;
    nan_nodata.output_type = "Float32";
    nan_nodata.nodata_value = std::nan("");
    extractLevel(kept, dir.path("none.tif"), nan_nodata);
    const Exported e2 = readExport(dir.path("none.tif"));
    ASSERT_TRUE(e2.has_nodata);
    EXPECT_TRUE(std::isnan(e2.nodata));
    int64_t nodata = 0;
    for (int y = 0; y < source.height; ++y)
        for (int x = 0; x < source.width; ++x) {
            const size_t i = size_t(y) * source.width + x;
            ASSERT_EQ(e2.isNodata(i), source.isVoid(x, y)) << x << "," << y;
            nodata += e2.isNodata(i);
        }
    EXPECT_EQ(nodata, 368);

    // all: today's behaviour, everything filled, the collar too.
    const BuildReport r3 = buildArchive(test::dataPath("everest_utm44.tif"), dir.path("all.ridge"),
                                        options(io::VoidFill::All));
    EXPECT_EQ(r3.voids_kept, 0);
    EXPECT_GT(r3.voids_filled, 5000);
}

TEST(KeptVoids, NevilleLevelsKeepNoSampleWhoseFilterSupportTouchesNodata)
{
    test::ScratchDir dir;
    const std::string source_path = test::dataPath("everest_utm44.tif");
    const Source source = readSource(source_path);
    const std::string archive_path = dir.path("neville.ridge");
    BuildOptions o = options(io::VoidFill::Interior, 17);
    o.filter = PyramidFilter::Neville4;
    buildArchive(source_path, archive_path, o);
    VerifyOptions v;
    v.source = source_path;
    const VerifyReport vr = verifyArchive(archive_path, v);
    ASSERT_TRUE(vr.ok()) << vr.problems.front();
    const archive::ArchiveReader reader(archive_path);
    const PyramidGeometry& g = reader.geometry();
    const int level = g.finestLevel() - 1; // supports of 9 finest samples per axis
    std::vector<uint8_t> valid;
    const CodeGrid grid = decodeLevelWindow(reader, level, 0, 0, g.validLevelWidth(level),
                                            g.validLevelHeight(level), {}, &valid);
    ASSERT_FALSE(valid.empty());
    for (int j = 0; j < grid.height; ++j)
        for (int i = 0; i < grid.width; ++i) {
            bool support_valid = true;
            for (int b = -4; b <= 4; ++b)
                for (int a = -4; a <= 4; ++a)
                    support_valid &= !source.isVoid(std::clamp(2 * i + a, 0, source.width - 1),
                                                    std::clamp(2 * j + b, 0, source.height - 1));
            ASSERT_EQ(valid[size_t(j) * grid.width + i] != 0, support_valid) << i << "," << j;
        }
}

TEST(KeptVoids, HillshadeLeavesNodataTransparent)
{
    test::ScratchDir dir;
    const std::string source_path = test::dataPath("everest_utm44.tif");
    const Source source = readSource(source_path);
    int64_t collar = 0;
    const std::vector<uint8_t> outside = borderConnectedVoids(source, collar);
    const std::string archive_path = dir.path("utm.ridge");
    buildArchive(source_path, archive_path, options(io::VoidFill::Interior));
    const std::string png = dir.path("shade.png");
    writeHillshade(archive_path, png, {});
    GDALDatasetH ds = GDALOpen(png.c_str(), GA_ReadOnly);
    ASSERT_NE(ds, nullptr);
    ASSERT_EQ(GDALGetRasterCount(ds), 4);
    std::vector<uint8_t> alpha(source.metres.size());
    ASSERT_EQ(GDALRasterIO(GDALGetRasterBand(ds, 4), GF_Read, 0, 0, source.width, source.height,
                           alpha.data(), source.width, source.height, GDT_Byte, 0, 0),
              CE_None);
    GDALClose(ds);
    for (size_t i = 0; i < alpha.size(); ++i)
        ASSERT_EQ(alpha[i], outside[i] ? 0 : 255) << i;
}

TEST(KeptVoids, VersionOneArchivesStillOpenDecodeAndExportWithoutNodata)
{
    // tests/data/v1_everest_40x30.ridge: written by ridge before format version 2 (README).
    test::ScratchDir dir;
    const std::string v1 = test::dataPath("v1_everest_40x30.ridge");
    const archive::ArchiveReader reader(v1);
    EXPECT_EQ(reader.header().version, 1u);
    EXPECT_FALSE(reader.storesValidity());
    EXPECT_EQ(reader.metadata().source.fill_voids, "all");
    EXPECT_EQ(reader.readValidity({0, 0, 0}).kind, PatchValidity::Kind::AllValid);
    const VerifyReport vr = verifyArchive(v1, {});
    ASSERT_TRUE(vr.ok()) << vr.problems.front();
    // Lossless: the finest level is the source window (everest_crop.tif, x 0..39, y 0..29).
    const Source everest = readSource(test::dataPath("everest_crop.tif"));
    std::vector<uint8_t> valid;
    const CodeGrid grid =
        decodeLevelWindow(reader, reader.geometry().finestLevel(), 0, 0, 40, 30, {}, &valid);
    EXPECT_TRUE(valid.empty());
    for (int y = 0; y < 30; ++y)
        for (int x = 0; x < 40; ++x)
            ASSERT_EQ(reader.quantization().toMetres(grid.at(x, y)),
                      everest.metres[size_t(y) * everest.width + x]);
    extractLevel(v1, dir.path("v1.tif"), {});
    EXPECT_FALSE(readExport(dir.path("v1.tif")).has_nodata);
}

TEST(KeptVoids, ExtractRefusesANodataValueThatIsARealHeight)
{
    test::ScratchDir dir;
    const std::string archive_path = dir.path("utm.ridge");
    buildArchive(test::dataPath("everest_utm44.tif"), archive_path,
                 options(io::VoidFill::Interior));
    const archive::ArchiveReader reader(archive_path);
    const CodeGrid grid =
        decodeLevelWindow(reader, reader.geometry().finestLevel(), 142, 111, 1, 1);
    ExtractOptions o;
    o.nodata_value = reader.quantization().toMetres(grid.codes[0]);
    try {
        extractLevel(archive_path, dir.path("bad.tif"), o);
        FAIL() << "a nodata value equal to a height was accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("nodata_value"), std::string::npos) << e.what();
    }
    EXPECT_FALSE(std::filesystem::exists(dir.path("bad.tif")));
    o.nodata_value = std::numeric_limits<double>::infinity();
    EXPECT_THROW(o.validate(), Error);
}

// The flip-every-region test of build_verify_test.cpp, on the bytes of the validity masks: a
// flipped mask byte is caught (by the blob's CRC) and blamed on the patch that holds it.
// Every flip costs a whole verify, so the test flips six bytes of the first eight bitmaps and
// the first mask byte of every seventh patch besides (and of the last): the blame is worked
// out per patch, so more patches of the same kinds only repeat the same path.
TEST(KeptVoids, FlippedMaskBytesAreReportedWithThePatchTheyHit)
{
    test::ScratchDir dir;
    const std::string good = dir.path("good.ridge");
    const std::string bad = dir.path("bad.ridge");
    buildArchive(test::dataPath("everest_utm44.tif"), good, options(io::VoidFill::Interior, 17));
    std::ifstream in(good, std::ios::binary);
    const std::vector<uint8_t> bytes{std::istreambuf_iterator<char>(in), {}};
    const archive::ArchiveReader reader(good);
    int bitmaps = 0;
    const int64_t patches = reader.geometry().patchCount();
    for (int64_t k = 0; k < patches; ++k) {
        const PatchId p = reader.geometry().patchAt(k);
        const archive::PatchRecord& r = reader.record(p);
        const size_t mask = r.offset + r.block_errors_size;
        const size_t mask_end = r.offset + reader.payloadOffset(p, reader.readBlob(p));
        std::vector<size_t> positions;
        if (mask_end - mask > 1) { // a bitmap: frame_size, then the first, middle, last frame byte
            if (++bitmaps <= 8)
                positions = {mask,        mask + 1, mask + 4, mask + 5, (mask + 5 + mask_end) / 2,
                             mask_end - 1};
        }
        if (positions.empty() && (k % 7 == 0 || k == patches - 1))
            positions = {mask};
        for (size_t pos : positions) {
            std::vector<uint8_t> flipped = bytes;
            flipped[pos] ^= 0x01;
            std::ofstream(bad, std::ios::binary | std::ios::trunc)
                .write(reinterpret_cast<const char*>(flipped.data()),
                       std::streamsize(flipped.size()));
            const VerifyReport v = verifyArchive(bad, {});
            ASSERT_FALSE(v.ok()) << "flip at mask byte " << pos << " went unnoticed";
            EXPECT_NE(v.problems.front().find(bad + ": " + archive::ArchiveReader::patchName(p)),
                      std::string::npos)
                << v.problems.front();
        }
    }
    EXPECT_GT(bitmaps, 5);
}
