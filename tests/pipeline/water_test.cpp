// Water that does not depend on lossy heights (issue 22): the build flags water per sample
// from the source's exact heights (`--sea-level`) and a water layer (`--water`), every level
// takes the finest flags at its positions, and `hillshade` paints by the flags. On the coastal
// fixture (tests/data/sfbay_coast.tif: the Pacific and the Bay at exactly 0 m) a progressive
// archive within 1 m decodes the sea as up to +1 m; before the flags, hillshade painted it as
// land.
#include "archive_bytes.h"
#include "archive_craft.h"
#include "test_support.h"

#include "ridge/archive/archive_reader.h"
#include "ridge/archive/sample_flags_storage.h"
#include "ridge/core/error.h"
#include "ridge/io/raster_source.h"
#include "ridge/pipeline/build.h"
#include "ridge/pipeline/height_query.h"
#include "ridge/pipeline/hillshade.h"
#include "ridge/pipeline/level_decoder.h"
#include "ridge/pipeline/verify.h"

#include <gdal.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>

using namespace ridge;

namespace {

struct Source {
    int width = 0, height = 0;
    std::vector<double> metres; // NaN at voids
    double at(int x, int y) const { return metres[size_t(y) * width + x]; }
};

Source readSource(const std::string& path)
{
    io::ReferenceRaster r(path, io::IngestOptions{});
    Source s{r.width(), r.height(), std::vector<double>(size_t(r.width()) * r.height())};
    r.readRows(0, s.height, s.metres.data());
    return s;
}

std::string build(const test::ScratchDir& dir, const std::string& name, BuildOptions options,
                  const std::string& source = test::dataPath("sfbay_coast.tif"))
{
    const std::string path = dir.path(name);
    buildArchive(source, path, options);
    return path;
}

BuildOptions lossy()
{
    BuildOptions o;
    o.codec = "progressive";
    o.max_error = 1.0;
    o.patch_size = 65;
    return o;
}

// The finest level's flags of an archive, one byte a sample (0 when it stores none).
std::vector<uint8_t> finestFlags(const std::string& archive)
{
    const archive::ArchiveReader reader(archive);
    const PyramidGeometry& g = reader.geometry();
    std::vector<uint8_t> valid, flags;
    decodeLevelWindow(reader, g.finestLevel(), 0, 0, g.width(), g.height(), {}, &valid, &flags);
    if (flags.empty())
        flags.assign(size_t(g.width()) * g.height(), 0);
    return flags;
}

// Water in the shared palette is blue over green and red; no land colour is.
bool looksLikeWater(const uint8_t* p)
{
    return p[2] > p[0] + 24 && p[2] > p[1] + 8;
}

} // namespace

TEST(Water, TheSeaIsFlaggedFromTheSourcesExactHeightsNotTheDecodedOnes)
{
    test::ScratchDir dir;
    const std::string archive = build(dir, "lossy.ridge", lossy());
    const Source source = readSource(test::dataPath("sfbay_coast.tif"));
    const std::vector<uint8_t> flags = finestFlags(archive);
    const archive::ArchiveReader reader(archive);
    const CodeGrid decoded = decodeLevel(reader, reader.geometry().finestLevel());
    int64_t sea = 0, sea_decoded_above_zero = 0;
    for (int y = 0; y < source.height; ++y)
        for (int x = 0; x < source.width; ++x) {
            const bool water = (flags[size_t(y) * source.width + x] & kSampleWater) != 0;
            ASSERT_EQ(water, source.at(x, y) <= 0.0) << "sample " << x << ", " << y;
            sea += water;
            sea_decoded_above_zero +=
                water && reader.quantization().toMetres(decoded.at(x, y)) > 0.0;
        }
    EXPECT_EQ(sea, 37024); // every 0 m sample of the fixture
    EXPECT_EQ(reader.metadata().water.samples, sea);
    // The premise: the lossy heights alone would have called much of the sea land.
    EXPECT_GT(sea_decoded_above_zero, sea / 10);
}

TEST(Water, EveryLevelTakesTheFinestFlagsAtItsPositionsInBothBuildPaths)
{
    test::ScratchDir dir;
    BuildOptions streamed; // lossless decimation without voids: the streaming build
    streamed.patch_size = 65;
    const std::string a = build(dir, "streamed.ridge", streamed);
    const std::string b = build(dir, "in_memory.ridge", lossy());
    const std::vector<uint8_t> finest = finestFlags(a);
    ASSERT_EQ(finest, finestFlags(b));
    for (const std::string& path : {a, b}) {
        const archive::ArchiveReader reader(path);
        const PyramidGeometry& g = reader.geometry();
        for (int l = 0; l < g.finestLevel(); ++l) {
            std::vector<uint8_t> valid, flags;
            decodeLevelWindow(reader, l, 0, 0, g.validLevelWidth(l), g.validLevelHeight(l), {},
                              &valid, &flags);
            ASSERT_FALSE(flags.empty()) << path << " level " << l;
            const int64_t s = g.step(l);
            for (int j = 0; j < g.validLevelHeight(l); ++j)
                for (int i = 0; i < g.validLevelWidth(l); ++i)
                    ASSERT_EQ(flags[size_t(j) * g.validLevelWidth(l) + i],
                              finest[size_t(j * s) * g.width() + size_t(i * s)])
                        << path << " level " << l << " sample " << i << ", " << j;
        }
    }
}

TEST(Water, SeaLevelMovesOrTurnsOffTheHeightRule)
{
    test::ScratchDir dir;
    const Source source = readSource(test::dataPath("sfbay_coast.tif"));
    BuildOptions o = lossy();
    o.ingest.sea_level = 50.0;
    const std::vector<uint8_t> at50 = finestFlags(build(dir, "at50.ridge", o));
    for (size_t k = 0; k < at50.size(); ++k)
        ASSERT_EQ((at50[k] & kSampleWater) != 0, source.metres[k] <= 50.0) << k;
    o.ingest.sea_level.reset();
    const std::string none = build(dir, "none.ridge", o);
    for (uint8_t f : finestFlags(none))
        ASSERT_EQ(f, 0);
    EXPECT_EQ(archive::ArchiveReader(none).metadata().water.samples, 0);
    EXPECT_FALSE(archive::ArchiveReader(none).metadata().water.sea_level.has_value());
}

TEST(Water, AVectorLayerInAnotherCrsAddsALakeAboveSeaLevel)
{
    test::ScratchDir dir;
    const Source source = readSource(test::dataPath("sfbay_coast.tif"));
    BuildOptions o = lossy();
    o.ingest.water_layer = test::dataPath("crystal_springs_utm10.geojson");
    const std::string archive = build(dir, "lake.ridge", o);
    const std::vector<uint8_t> flags = finestFlags(archive);
    // The polygon is the outline of the reservoir's flat 87 m surface (tests/data/README.md):
    // every water sample above sea level is on it, and nearly all of its 269 samples are water
    // (pixel centres inside the reprojected polygon).
    int64_t lake = 0;
    for (size_t k = 0; k < flags.size(); ++k)
        if ((flags[k] & kSampleWater) && source.metres[k] > 0.0) {
            ASSERT_EQ(source.metres[k], 87.0)
                << "sample " << k % source.width << ", " << k / source.width;
            ++lake;
        }
    EXPECT_GE(lake, 250);
    EXPECT_LE(lake, 269);
    const archive::ArchiveReader reader(archive);
    EXPECT_EQ(reader.metadata().water.samples, 37024 + lake);
    EXPECT_EQ(reader.metadata().water.layer, test::dataPath("crystal_springs_utm10.geojson"));
}

TEST(Water, ARasterLayerOnAnotherGridIsResampledOntoTheArchives)
{
    test::ScratchDir dir;
    // The lake burnt into a 30 m UTM raster (0 land, 1 water, 255 nodata outside the lake's
    // neighbourhood) by gdal_rasterize: another CRS, another spacing, a smaller extent.
    const std::string lake = dir.path("lake_utm.tif");
    const test::CommandResult made =
        test::runShell("gdal_rasterize -q -burn 1 -init 0 -a_nodata 255 -tr 30 30 -ot Byte " +
                       test::dataPath("crystal_springs_utm10.geojson") + " " + lake);
    ASSERT_EQ(made.exit_code, 0) << made.output;
    const Source source = readSource(test::dataPath("sfbay_coast.tif"));
    BuildOptions o = lossy();
    o.ingest.sea_level.reset();
    o.ingest.water_layer = lake;
    const std::vector<uint8_t> flags = finestFlags(build(dir, "lake.ridge", o));
    int64_t lake_samples = 0;
    for (size_t k = 0; k < flags.size(); ++k)
        if (flags[k] & kSampleWater) {
            // Nearest resampling of 30 m cells onto ~80 m samples: the lake give or take its
            // rim, never the sea or the hills.
            ASSERT_NEAR(source.metres[k], 87.0, 12.0) << k;
            ++lake_samples;
        }
    EXPECT_GE(lake_samples, 230);
    EXPECT_LE(lake_samples, 300);
}

TEST(Water, AWaterLayerThatIsNotGeodataIsRefusedNamingIt)
{
    test::ScratchDir dir;
    const std::string junk = dir.path("lakes.txt");
    FILE* f = std::fopen(junk.c_str(), "w");
    std::fputs("not a raster nor a vector\n", f);
    std::fclose(f);
    BuildOptions o = lossy();
    o.ingest.water_layer = junk;
    try {
        build(dir, "x.ridge", o);
        FAIL() << "built with a water layer that is not one";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find(junk), std::string::npos) << e.what();
    }
    EXPECT_FALSE(std::filesystem::exists(dir.path("x.ridge")));
}

TEST(Water, HillshadeOfALossyArchivePaintsTheSeaAsWater)
{
    test::ScratchDir dir;
    const std::string archive = build(dir, "lossy.ridge", lossy());
    const std::string png = dir.path("shade.png");
    HillshadeOptions options;
    writeHillshade(archive, png, options);
    GDALDatasetH ds = GDALOpen(png.c_str(), GA_ReadOnly);
    ASSERT_NE(ds, nullptr);
    const int w = GDALGetRasterXSize(ds), h = GDALGetRasterYSize(ds);
    std::vector<uint8_t> rgb(size_t(w) * h * 3);
    ASSERT_EQ(GDALDatasetRasterIO(ds, GF_Read, 0, 0, w, h, rgb.data(), w, h, GDT_Byte, 3, nullptr,
                                  3, 3 * w, 1),
              CE_None);
    GDALClose(ds);
    const Source source = readSource(test::dataPath("sfbay_coast.tif"));
    int64_t sea = 0, sea_as_water = 0, land_as_water = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const bool water = looksLikeWater(&rgb[(size_t(y) * w + x) * 3]);
            if (source.at(x, y) <= 0.0) {
                ++sea;
                sea_as_water += water;
            } else {
                land_as_water += water;
            }
        }
    EXPECT_EQ(sea_as_water, sea);
    EXPECT_EQ(land_as_water, 0);
}

TEST(Water, FilledVoidsAreFlaggedAndKeptNodataHasNoFlag)
{
    test::ScratchDir dir;
    BuildOptions o;
    o.patch_size = 65;
    o.ingest.fill_voids = io::VoidFill::All;
    const std::string filled = build(dir, "filled.ridge", o, test::dataPath("rainier_voids.tif"));
    const Source source = readSource(test::dataPath("rainier_voids.tif"));
    const std::vector<uint8_t> flags = finestFlags(filled);
    int64_t voids = 0;
    for (size_t k = 0; k < flags.size(); ++k) {
        const bool is_void = std::isnan(source.metres[k]);
        voids += is_void;
        ASSERT_EQ((flags[k] & kSampleFilled) != 0, is_void) << k;
        ASSERT_EQ(flags[k] & kSampleWater, 0) << k; // Rainier is 347..1994 m
    }
    EXPECT_EQ(voids, 368);
    o.ingest.fill_voids = io::VoidFill::None;
    for (uint8_t f : finestFlags(build(dir, "kept.ridge", o, test::dataPath("rainier_voids.tif"))))
        ASSERT_EQ(f, 0);
}

TEST(Water, QueriesReportWaterAndFilledSamplesAsTheArchiveFlagsThem)
{
    test::ScratchDir dir;
    const Source source = readSource(test::dataPath("sfbay_coast.tif"));
    BuildOptions o = lossy();
    o.ingest.water_layer = test::dataPath("crystal_springs_utm10.geojson");
    HeightQuery query(build(dir, "lossy.ridge", o));
    const std::vector<uint8_t> flags = finestFlags(query.reader().path());
    int64_t sea_above_zero = 0, checked = 0;
    for (int y = 0; y < source.height; y += 3)
        for (int x = 0; x < source.width; x += 3) {
            // At a sample centre both resamplings read that sample alone.
            for (QueryResampling r : {QueryResampling::Nearest, QueryResampling::Bilinear}) {
                const HeightSample s = query.sample({x + 0.5, y + 0.5}, PointSpace::Pixel, -1, r);
                ASSERT_TRUE(s.on_raster);
                ASSERT_EQ(s.water, (flags[size_t(y) * source.width + x] & kSampleWater) != 0)
                    << x << ", " << y;
                ASSERT_FALSE(s.filled);
                sea_above_zero += s.water && source.at(x, y) <= 0.0 && s.height > 0.0;
                ++checked;
            }
        }
    EXPECT_GT(sea_above_zero, 0) << "sea decoded above 0 m is still water";
    // Between samples (bilinear): water where the blend of the four water bits is >= 1/2;
    // the reservoir's samples around (189, 294) are all 87 m and in the lake polygon.
    const HeightSample lake = query.sample({189.9, 294.8}, PointSpace::Pixel);
    EXPECT_EQ(source.at(189, 294), 87.0);
    EXPECT_TRUE(lake.water) << "the reservoir, 87 m above the sea";

    BuildOptions fill;
    fill.patch_size = 65;
    fill.ingest.fill_voids = io::VoidFill::All;
    HeightQuery filled(build(dir, "filled.ridge", fill, test::dataPath("rainier_voids.tif")));
    const Source rainier = readSource(test::dataPath("rainier_voids.tif"));
    int64_t voids = 0;
    for (int y = 0; y < rainier.height; ++y)
        for (int x = 0; x < rainier.width; ++x) {
            const HeightSample s =
                filled.sample({x + 0.5, y + 0.5}, PointSpace::Pixel, -1, QueryResampling::Nearest);
            ASSERT_EQ(s.filled, std::isnan(rainier.at(x, y))) << x << ", " << y;
            voids += s.filled;
        }
    EXPECT_EQ(voids, 368);
}

TEST(Water, VerifyChecksTheFlagsAcrossLevelsAndAgainstTheSource)
{
    test::ScratchDir dir;
    BuildOptions o = lossy();
    o.ingest.water_layer = test::dataPath("crystal_springs_utm10.geojson");
    const std::string path = build(dir, "coast.ridge", o);
    VerifyOptions with_source;
    with_source.source = test::dataPath("sfbay_coast.tif");
    VerifyReport clean = verifyArchive(path, with_source);
    EXPECT_TRUE(clean.ok()) << (clean.problems.empty() ? "" : clean.problems.front());

    // A patch of land whose flags byte says "all water": a valid encoding, a wrong one.
    const archive::ArchiveReader reader(path);
    const PyramidGeometry& g = reader.geometry();
    std::optional<PatchId> land;
    for (int l = g.finestLevel(); l >= 0 && !land; --l)
        for (int y = 0; y < g.patchesY(l) && !land; ++y)
            for (int x = 0; x < g.patchesX(l) && !land; ++x)
                if (reader.readSampleFlags({l, x, y}).kind == PatchSampleFlags::Kind::None &&
                    reader.readValidity({l, x, y}).kind == PatchValidity::Kind::AllValid)
                    land = PatchId{l, x, y};
    ASSERT_TRUE(land.has_value());
    const archive::PatchRecord& r = reader.record(*land);
    test::ArchiveBytes bytes(path);
    // Block errors (none stored), the one-byte validity kind, then the flags' kind.
    ASSERT_EQ(r.block_errors_size, 0u);
    bytes.bytes()[r.offset + 1] = 1;
    bytes.reseal();
    const std::string crafted = dir.path("crafted.ridge");
    bytes.save(crafted);
    const VerifyReport plain = verifyArchive(crafted, {});
    ASSERT_FALSE(plain.ok()) << "patch (" << land->level << ", " << land->x << ", " << land->y
                             << ")";
    bool named = false;
    for (const std::string& p : plain.problems)
        named = named || p.find("sample flags (all water) differ") != std::string::npos ||
                p.find("water.samples") != std::string::npos;
    EXPECT_TRUE(named) << plain.problems.front();
    if (land->level == g.finestLevel()) {
        const VerifyReport checked = verifyArchive(crafted, with_source);
        bool extra = false;
        for (const std::string& p : checked.problems)
            extra = extra || p.find("flagged water above the sea level") != std::string::npos;
        // With a water layer named, extra water cannot be refuted by the source.
        EXPECT_FALSE(extra);
    }
}

TEST(Water, VerifySourceRefutesWaterAndFilledFlagsTheSourceDoesNotSupport)
{
    test::ScratchDir dir;
    // Without a layer: every water sample must be at or below the sea level in the source.
    BuildOptions o = lossy();
    const std::string path = build(dir, "coast.ridge", o);
    const archive::ArchiveReader reader(path);
    const PyramidGeometry& g = reader.geometry();
    const int L = g.finestLevel();
    std::optional<PatchId> land;
    for (int y = 0; y < g.patchesY(L) && !land; ++y)
        for (int x = 0; x < g.patchesX(L) && !land; ++x)
            if (reader.readSampleFlags({L, x, y}).kind == PatchSampleFlags::Kind::None)
                land = PatchId{L, x, y};
    ASSERT_TRUE(land.has_value());
    test::ArchiveBytes bytes(path);
    bytes.bytes()[reader.record(*land).offset + 1] = 1; // all water
    bytes.reseal();
    const std::string crafted = dir.path("crafted.ridge");
    bytes.save(crafted);
    VerifyOptions with_source;
    with_source.source = test::dataPath("sfbay_coast.tif");
    const VerifyReport report = verifyArchive(crafted, with_source);
    bool extra = false;
    for (const std::string& p : report.problems)
        extra = extra || p.find("flagged water above the sea level") != std::string::npos;
    EXPECT_TRUE(extra) << (report.problems.empty() ? "ok" : report.problems.front());

    // Filled voids: a Rainier archive verifies clean, and with a finest patch's flags
    // re-encoded without its filled samples (and, to keep the pyramid consistent, nothing
    // else changed: the coarse patches still say what the finest did) --source refutes it.
    BuildOptions fill;
    fill.patch_size = 65;
    fill.ingest.fill_voids = io::VoidFill::All;
    const std::string rainier =
        build(dir, "rainier.ridge", fill, test::dataPath("rainier_voids.tif"));
    VerifyOptions rainier_source;
    rainier_source.source = test::dataPath("rainier_voids.tif");
    const VerifyReport fine = verifyArchive(rainier, rainier_source);
    EXPECT_TRUE(fine.ok()) << (fine.problems.empty() ? "" : fine.problems.front());
    const archive::ArchiveReader rr(rainier);
    const PyramidGeometry& rg = rr.geometry();
    const int RL = rg.finestLevel();
    std::optional<PatchId> holes;
    for (int y = 0; y < rg.patchesY(RL) && !holes; ++y)
        for (int x = 0; x < rg.patchesX(RL) && !holes; ++x)
            if (rr.readSampleFlags({RL, x, y}).kind == PatchSampleFlags::Kind::Mixed)
                holes = PatchId{RL, x, y};
    ASSERT_TRUE(holes.has_value());
    const std::vector<uint8_t> blob = rr.readBlob(*holes);
    const size_t flags_at = rr.record(*holes).block_errors_size +
                            test::validityMaskSize(blob, rr.record(*holes).block_errors_size);
    PatchSampleFlags stored;
    size_t stored_size = 0;
    ASSERT_EQ(archive::unpackSampleFlags(blob.data() + flags_at, blob.size() - flags_at,
                                         rg.patchSize(), nullptr, stored, stored_size),
              "");
    test::ArchiveBytes edited(rainier);
    test::replaceBlobBytes(edited, size_t(rg.patchIndex(*holes)), flags_at, flags_at + stored_size,
                           archive::noSampleFlags());
    edited.reseal();
    const std::string crafted_rainier = dir.path("rainier_crafted.ridge");
    edited.save(crafted_rainier);
    const VerifyReport refuted = verifyArchive(crafted_rainier, rainier_source);
    bool filled = false;
    for (const std::string& p : refuted.problems)
        filled = filled || p.find("flagged filled where the build filled no void, or not") !=
                               std::string::npos;
    EXPECT_TRUE(filled) << (refuted.problems.empty() ? "ok" : refuted.problems.front());
}

// Format 5 on context-codes the flag bitmaps (kind 3); version 4 archives, zstd bitmaps (kind
// 2), still read with the same flags and verify against their source. Each version has one
// bitmap kind: a version 5 or later archive holding kind 2 is refused, naming the patch and
// the kind.
TEST(Water, Version4ArchivesWithZstdBitmapsStillReadAndLaterVersionsRefuseThem)
{
    test::ScratchDir dir;
    BuildOptions fill = lossy();
    fill.ingest.fill_voids = io::VoidFill::All;
    const std::string current = build(dir, "coast.ridge", fill);
    const archive::ArchiveReader reader(current);
    ASSERT_EQ(reader.header().version, archive::kFormatVersion);
    const PyramidGeometry& g = reader.geometry();
    const int n = g.patchSize();
    // Each mixed patch's flags re-encoded as version 4 wrote them (replaceBlobBytes moves
    // the blobs after it and their offsets).
    test::ArchiveBytes v4(current), mixed_kind2(current);
    size_t rewritten = 0, current_bytes = 0, v4_bytes = 0;
    for (int64_t i = g.patchCount() - 1; i >= 0; --i) {
        const PatchId p = g.patchAt(i);
        const PatchSampleFlags flags = reader.readSampleFlags(p);
        if (flags.kind != PatchSampleFlags::Kind::Mixed)
            continue;
        const std::vector<uint8_t> blob = reader.readBlob(p);
        const size_t at = reader.record(p).block_errors_size +
                          test::validityMaskSize(blob, reader.record(p).block_errors_size);
        ASSERT_EQ(blob.at(at), 3) << reader.describe(p);
        PatchSampleFlags stored;
        size_t size = 0;
        ASSERT_EQ(archive::unpackSampleFlags(blob.data() + at, blob.size() - at, n, nullptr, stored,
                                             size),
                  "");
        const std::vector<uint8_t> zstd = archive::packSampleFlags(flags, n, 4);
        ASSERT_EQ(zstd.at(0), 2);
        test::replaceBlobBytes(v4, size_t(i), at, at + size, zstd);
        if (rewritten == 0)
            test::replaceBlobBytes(mixed_kind2, size_t(i), at, at + size, zstd);
        ++rewritten;
        current_bytes += size;
        v4_bytes += zstd.size();
    }
    ASSERT_GT(rewritten, 2u) << "the fixture's coast crosses several patches";
    EXPECT_LT(current_bytes, v4_bytes) << "context coding is smaller on a real coast";
    v4.storeIndexUnpacked();    // version 4's index: the entries as they are
    v4.storeMetadataUnpacked(); // and its metadata
    v4.set<uint32_t>(8, 4);     // header version
    v4.reseal();
    const std::string v4_path = dir.path("coast_v4.ridge");
    v4.save(v4_path);
    EXPECT_EQ(finestFlags(v4_path), finestFlags(current));
    VerifyOptions with_source;
    with_source.source = test::dataPath("sfbay_coast.tif");
    const VerifyReport report = verifyArchive(v4_path, with_source);
    EXPECT_TRUE(report.ok()) << (report.problems.empty() ? "" : report.problems.front());

    mixed_kind2.reseal();
    const std::string refused = dir.path("coast_kind2_in_current.ridge");
    mixed_kind2.save(refused);
    const VerifyReport bad = verifyArchive(refused, VerifyOptions{});
    ASSERT_FALSE(bad.ok());
    bool named = false;
    for (const std::string& p : bad.problems)
        named = named || p.find("format version " + std::to_string(archive::kFormatVersion) +
                                " codes bitmaps as kind 3") != std::string::npos;
    EXPECT_TRUE(named) << bad.problems.front();
}
