// Sharded builds (pipeline/shard.h): the merged archive is byte-identical to `ridge build`
// of the same raster, for every codec family and shard level; hostile plans, files and
// inputs are refused naming the shard, with nothing left at the output.
#include "ridge/archive/shard_file.h"
#include "ridge/core/error.h"
#include "ridge/pipeline/build.h"
#include "ridge/pipeline/shard.h"
#include "ridge/pipeline/verify.h"

#include "test_support.h"

#include <gdal.h>
#include <gdal_utils.h>
#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace ridge {
namespace {

namespace fs = std::filesystem;
using test::ScratchDir;

// gdal_translate -srcwin of the Everest fixture into `out` (a GeoTIFF).
void cutTile(const std::string& source, int x, int y, int w, int h, const std::string& out)
{
    GDALAllRegister();
    GDALDatasetH src = GDALOpen(source.c_str(), GA_ReadOnly);
    ASSERT_NE(src, nullptr);
    const std::string args[] = {"-srcwin", std::to_string(x), std::to_string(y), std::to_string(w),
                                std::to_string(h)};
    std::vector<char*> argv;
    for (const std::string& a : args)
        argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    GDALTranslateOptions* options = GDALTranslateOptionsNew(argv.data(), nullptr);
    GDALDatasetH dst = GDALTranslate(out.c_str(), src, options, nullptr);
    GDALTranslateOptionsFree(options);
    ASSERT_NE(dst, nullptr);
    GDALClose(dst);
    GDALClose(src);
}

// Raises a 10 x 10 block of `tile`'s samples by 1 m in place: the tile stays where it is.
void editTile(const std::string& tile)
{
    GDALDatasetH ds = GDALOpen(tile.c_str(), GA_Update);
    ASSERT_NE(ds, nullptr);
    GDALRasterBandH band = GDALGetRasterBand(ds, 1);
    std::vector<int16_t> block(100);
    ASSERT_EQ(GDALRasterIO(band, GF_Read, 40, 40, 10, 10, block.data(), 10, 10, GDT_Int16, 0, 0),
              CE_None);
    for (int16_t& v : block)
        ++v;
    ASSERT_EQ(GDALRasterIO(band, GF_Write, 40, 40, 10, 10, block.data(), 10, 10, GDT_Int16, 0, 0),
              CE_None);
    GDALClose(ds);
}

// The Everest fixture as Float32 heights that no 16-bit integer holds (v · 0.37 + 0.123 m),
// written to `out`.
void floatEverest(const std::string& out)
{
    GDALAllRegister();
    GDALDatasetH src = GDALOpen(test::dataPath("everest_crop.tif").c_str(), GA_ReadOnly);
    ASSERT_NE(src, nullptr);
    const int w = GDALGetRasterXSize(src), h = GDALGetRasterYSize(src);
    std::vector<float> v(size_t(w) * h);
    ASSERT_EQ(GDALRasterIO(GDALGetRasterBand(src, 1), GF_Read, 0, 0, w, h, v.data(), w, h,
                           GDT_Float32, 0, 0),
              CE_None);
    for (float& x : v)
        x = x * 0.37f + 0.123f;
    GDALDatasetH dst =
        GDALCreate(GDALGetDriverByName("GTiff"), out.c_str(), w, h, 1, GDT_Float32, nullptr);
    ASSERT_NE(dst, nullptr);
    double gt[6];
    GDALGetGeoTransform(src, gt);
    GDALSetGeoTransform(dst, gt);
    GDALSetProjection(dst, GDALGetProjectionRef(src));
    ASSERT_EQ(GDALRasterIO(GDALGetRasterBand(dst, 1), GF_Write, 0, 0, w, h, v.data(), w, h,
                           GDT_Float32, 0, 0),
              CE_None);
    GDALClose(dst);
    GDALClose(src);
}

// The four tiles of the Everest fixture (301 x 203), sharing their edge column and row as
// SRTM tiles do.
std::vector<std::string> everestTiles(const ScratchDir& dir)
{
    const std::string source = test::dataPath("everest_crop.tif");
    std::vector<std::string> tiles;
    for (int ty = 0; ty < 2; ++ty)
        for (int tx = 0; tx < 2; ++tx) {
            tiles.push_back(dir.path("t" + std::to_string(tx) + std::to_string(ty) + ".tif"));
            cutTile(source, tx * 150, ty * 101, 151, 102, tiles.back());
        }
    return tiles;
}

BuildOptions optionsFor(const std::string& codec)
{
    BuildOptions o;
    o.patch_size = 17;
    o.codec = codec;
    if (codec != "lossless")
        o.max_error = 1.0;
    return o;
}

// The whole sharded build through the library, every step in its own call as the driver
// runs them; returns the merged archive's path.
std::string shardedBuild(const ShardPlan& plan, const ScratchDir& dir, const std::string& name)
{
    std::vector<std::string> summaries, segments;
    for (const PlanShard& s : plan.shards) {
        summaries.push_back(dir.path(name + ".s" + std::to_string(s.id)));
        buildShardSummary(plan, s.id, summaries.back());
    }
    std::string top = dir.path(name + ".top0");
    ShardStepReport r = coordinate(plan, summaries, "", {}, top);
    for (int stage = 1; r.pending_stage != 0; ++stage) {
        EXPECT_EQ(r.pending_stage, stage);
        std::vector<std::string> observations;
        for (const PlanShard& s : plan.shards) {
            observations.push_back(dir.path(name + ".o" + std::to_string(s.id)));
            observeShard(plan, s.id, top, observations.back());
        }
        const std::string next = dir.path(name + ".top" + std::to_string(stage));
        r = coordinate(plan, summaries, top, observations, next);
        top = next;
    }
    segments.push_back(top);
    for (const PlanShard& s : plan.shards) {
        segments.push_back(dir.path(name + ".g" + std::to_string(s.id)));
        buildShardSegment(plan, s.id, top, segments.back());
    }
    const std::string out = dir.path(name + ".ridge");
    mergeShards(plan, segments, out);
    return out;
}

class ShardedBuild : public ::testing::TestWithParam<const char*> {};

TEST_P(ShardedBuild, MergedArchiveIsByteIdenticalToOneProcessBuild)
{
    ScratchDir dir;
    const std::vector<std::string> tiles = everestTiles(dir);
    const BuildOptions options = optionsFor(GetParam());
    const ShardPlan plan = makePlan(tiles, options, 2, dir.path("plan.json"));
    ASSERT_EQ(plan.shards.size(), 6u); // level 2 of 6: 3 x 2 patches
    ASSERT_EQ(plan.source, dir.path("plan.vrt"));
    const std::string sharded = shardedBuild(loadPlan(dir.path("plan.json")), dir, "sharded");
    const std::string single = dir.path("single.ridge");
    buildArchive(plan.source, single, options);
    const std::string a = test::readFile(sharded), b = test::readFile(single);
    ASSERT_FALSE(a.empty());
    EXPECT_TRUE(a == b) << GetParam() << ": " << a.size() << " vs " << b.size() << " bytes";
    VerifyOptions verify;
    verify.source = plan.source;
    EXPECT_TRUE(verifyArchive(sharded, verify).ok());
}

INSTANTIATE_TEST_SUITE_P(Codecs, ShardedBuild,
                         ::testing::Values("lossless", "progressive", "jpeg2000"));

TEST(ShardedBuildLevels, EveryShardLevelGivesTheSameArchive)
{
    ScratchDir dir;
    const std::string source = test::dataPath("everest_crop.tif");
    for (const char* codec : {"lossless", "progressive"}) {
        const BuildOptions options = optionsFor(codec);
        const std::string single = dir.path(std::string(codec) + ".ridge");
        buildArchive(source, single, options);
        for (int k : {0, 1, 5}) { // one shard; four; every finest patch its own shard
            SCOPED_TRACE(std::string(codec) + " level " + std::to_string(k));
            const std::string plan_path = dir.path("plan" + std::to_string(k) + ".json");
            makePlan({source}, options, k, plan_path);
            const std::string sharded =
                shardedBuild(loadPlan(plan_path), dir, std::string(codec) + std::to_string(k));
            EXPECT_TRUE(test::readFile(sharded) == test::readFile(single));
        }
    }
}

// The message of the Error `f` throws ("" when it throws none).
template <typename F> std::string errorOf(F&& f)
{
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

nlohmann::json readJson(const std::string& path)
{
    return nlohmann::json::parse(test::readFile(path));
}

void writeJson(const std::string& path, const nlohmann::json& j)
{
    std::ofstream(path) << j.dump(1);
}

TEST(ShardedBuildFloat, AFloatMosaicIsQuantizedAsOneRaster)
{
    // Float32 tiles: the plan settles the code mapping over the whole mosaic (each tile's own
    // survey would give other codes), and every shard reads by it.
    ScratchDir dir;
    const std::string whole = dir.path("float.tif");
    floatEverest(whole);
    std::vector<std::string> tiles;
    for (int ty = 0; ty < 2; ++ty)
        for (int tx = 0; tx < 2; ++tx) {
            tiles.push_back(dir.path("f" + std::to_string(tx) + std::to_string(ty) + ".tif"));
            cutTile(whole, tx * 150, ty * 101, 151, 102, tiles.back());
        }
    for (const char* codec : {"lossless", "progressive"}) {
        SCOPED_TRACE(codec);
        BuildOptions options = optionsFor(codec);
        options.max_error =
            codec == std::string("lossless") ? std::nullopt : std::optional<double>(1.5);
        if (codec == std::string("lossless"))
            options.ingest.max_error = 0.05; // the quantization step's half
        const ShardPlan plan = makePlan(tiles, options, 2, dir.path(std::string(codec) + ".json"));
        ASSERT_TRUE(plan.options.ingest.code_mapping.has_value());
        EXPECT_FALSE(plan.options.ingest.code_mapping->exact);
        const std::string sharded = shardedBuild(loadPlan(plan.path), dir, codec);
        const std::string single = dir.path(std::string(codec) + "-single.ridge");
        buildArchive(plan.source, single, options);
        EXPECT_TRUE(test::readFile(sharded) == test::readFile(single));
        VerifyOptions verify;
        verify.source = plan.source;
        EXPECT_TRUE(verifyArchive(sharded, verify).ok());
    }
}

TEST(ShardPlan, EditedPlansAreRefusedNamingWhatIsWrong)
{
    ScratchDir dir;
    const std::string source = test::dataPath("everest_crop.tif");
    const std::string good = dir.path("plan.json");
    makePlan({source}, optionsFor("lossless"), 2, good);
    const nlohmann::json plan = readJson(good);
    const std::string bad = dir.path("bad.json");
    auto refusal = [&](const nlohmann::json& edited) {
        writeJson(bad, edited);
        return errorOf([&] { loadPlan(bad); });
    };
    EXPECT_EQ(refusal(plan), ""); // unedited: loads

    nlohmann::json overlap = plan;
    overlap["shards"][1]["window"][0] = 100; // into shard 0's columns
    EXPECT_NE(refusal(overlap).find("shard 1: its root or window"), std::string::npos)
        << refusal(overlap);
    nlohmann::json missing = plan;
    missing["shards"].erase(3);
    EXPECT_NE(refusal(missing).find("shard 3 is missing"), std::string::npos) << refusal(missing);
    nlohmann::json twice = plan;
    twice["shards"][2] = twice["shards"][1];
    EXPECT_NE(refusal(twice).find("shards[2] is shard 1"), std::string::npos) << refusal(twice);
    nlohmann::json hash = plan;
    hash["shards"][4]["hash"] = "0123456789abcdef";
    EXPECT_NE(refusal(hash).find("shard 4: hash"), std::string::npos) << refusal(hash);
    nlohmann::json option = plan;
    option["build"]["codec"] = "jpeg2000"; // hashes left as they were
    EXPECT_NE(refusal(option).find("layout_hash"), std::string::npos) << refusal(option);
    nlohmann::json type = plan;
    type["shard_level"] = "two";
    EXPECT_NE(refusal(type).find("shard_level is not an integer"), std::string::npos);
    nlohmann::json range = plan;
    range["build"]["patch_size"] = 100000;
    EXPECT_NE(refusal(range).find("build.patch_size"), std::string::npos);
    nlohmann::json input = plan;
    input["shards"][0]["inputs"] = {7};
    EXPECT_NE(refusal(input).find("shard 0: input 7 does not exist"), std::string::npos);
    std::ofstream(bad) << "{\"ridge_plan\": 1,";
    EXPECT_NE(errorOf([&] { loadPlan(bad); }).find("not JSON"), std::string::npos);
    EXPECT_NE(errorOf([&] { loadPlan(dir.path("absent.json")); }).find("cannot open"),
              std::string::npos);
}

TEST(ShardPlan, RefusesWhatAShardCannotBuildExactly)
{
    ScratchDir dir;
    const std::string source = test::dataPath("everest_crop.tif");
    BuildOptions neville = optionsFor("lossless");
    neville.filter = PyramidFilter::Neville4;
    EXPECT_NE(errorOf([&] {
                  makePlan({source}, neville, 2, dir.path("p.json"));
              }).find("decimation filter only"),
              std::string::npos);
    EXPECT_NE(errorOf([&] {
                  makePlan({source}, optionsFor("lossless"), 9, dir.path("p.json"));
              }).find("--shard-level 9: must be 0..5"),
              std::string::npos);
    EXPECT_FALSE(fs::exists(dir.path("p.json")));
}

TEST(ShardSteps, VoidsAndChangedInputsAreRefusedNamingTheShard)
{
    ScratchDir dir;
    // Rainier's voids lie inside the raster: the shards that meet them refuse.
    const ShardPlan voids = makePlan({test::dataPath("rainier_voids.tif")}, optionsFor("lossless"),
                                     1, dir.path("v.json"));
    std::string refusals;
    for (const PlanShard& s : voids.shards)
        refusals += errorOf([&] { buildShardSummary(voids, s.id, dir.path("v.sum")); });
    EXPECT_NE(refusals.find("nodata samples in its window"), std::string::npos) << refusals;
    EXPECT_NE(refusals.find("shard "), std::string::npos);

    const std::vector<std::string> tiles = everestTiles(dir);
    const ShardPlan plan = makePlan(tiles, optionsFor("lossless"), 2, dir.path("plan.json"));
    editTile(tiles[3]); // t11
    const std::string message = errorOf([&] { buildShardSummary(plan, 5, dir.path("s5")); });
    EXPECT_NE(message.find("shard 5: input " + tiles[3]), std::string::npos) << message;
    EXPECT_NE(message.find("changed since the plan"), std::string::npos);
    // Shard 0 lies under t00 only... and the shared row/column of the other tiles.
    EXPECT_EQ(errorOf([&] { buildShardSummary(plan, 0, dir.path("s0")); }), "");
    EXPECT_FALSE(fs::exists(dir.path("s5")));
}

TEST(ShardSteps, UnchangedStepsAreSkippedAndOnlyChangedShardsRebuilt)
{
    ScratchDir dir;
    std::vector<std::string> tiles = everestTiles(dir);
    const BuildOptions options = optionsFor("lossless");
    ShardPlan plan = makePlan(tiles, options, 2, dir.path("plan.json"));
    shardedBuild(plan, dir, "a");
    for (const PlanShard& s : plan.shards)
        EXPECT_TRUE(
            buildShardSummary(plan, s.id, dir.path("a.s" + std::to_string(s.id)), true).skipped);
    // t00 (columns 0..150, rows 0..101) changes: re-plan; the shards over it rebuild.
    editTile(tiles[0]);
    plan = makePlan(tiles, options, 2, dir.path("plan.json"));
    std::vector<int64_t> rebuilt;
    for (const PlanShard& s : plan.shards)
        if (!buildShardSummary(plan, s.id, dir.path("a.s" + std::to_string(s.id)), true).skipped)
            rebuilt.push_back(s.id);
    // Windows meeting columns 0..150 x rows 0..101: shards 0 and 1 (rows 0..128).
    EXPECT_EQ(rebuilt, (std::vector<int64_t>{0, 1}));
}

TEST(ShardMerge, HostileSegmentsAreRefusedAndNothingIsLeft)
{
    ScratchDir dir;
    const std::vector<std::string> tiles = everestTiles(dir);
    const ShardPlan plan = makePlan(tiles, optionsFor("progressive"), 2, dir.path("plan.json"));
    shardedBuild(plan, dir, "a");
    std::vector<std::string> files = {dir.path("a.top1")};
    for (const PlanShard& s : plan.shards)
        files.push_back(dir.path("a.g" + std::to_string(s.id)));
    const std::string out = dir.path("out.ridge");
    auto refusal = [&](const std::vector<std::string>& given) {
        const std::string message = errorOf([&] { mergeShards(plan, given, out); });
        EXPECT_FALSE(fs::exists(out)) << message;
        EXPECT_TRUE(test::temporariesIn(dir.dir()).empty());
        return message;
    };
    EXPECT_EQ(refusal({}).find("no top file"), 0u);

    std::vector<std::string> missing = files;
    missing.erase(missing.begin() + 3); // shard 2's
    EXPECT_NE(refusal(missing).find("shard 2: no segment given"), std::string::npos);
    std::vector<std::string> twice = files;
    twice.push_back(files[2]);
    EXPECT_NE(refusal(twice).find("a second segment of shard 1"), std::string::npos);

    // Truncated by a byte, and one payload byte flipped.
    const std::string cut = dir.path("cut.seg");
    std::string bytes = test::readFile(files[4]);
    std::ofstream(cut, std::ios::binary) << bytes.substr(0, bytes.size() - 1);
    std::vector<std::string> truncated = files;
    truncated[4] = cut;
    EXPECT_NE(refusal(truncated).find("cut.seg: not a ridge shard file"), std::string::npos);
    const std::string flipped = dir.path("flip.seg");
    bytes[100] ^= 0x40;
    std::ofstream(flipped, std::ios::binary) << bytes;
    std::vector<std::string> damaged = files;
    damaged[4] = flipped;
    EXPECT_NE(refusal(damaged).find("CRC-32 mismatch"), std::string::npos) << refusal(damaged);

    // A segment of the same shard from another plan (another bound) and a summary in place
    // of a segment.
    BuildOptions other = optionsFor("progressive");
    other.max_error = 2.0;
    ScratchDir elsewhere;
    const ShardPlan plan2 =
        makePlan(everestTiles(elsewhere), other, 2, elsewhere.path("plan.json"));
    shardedBuild(plan2, elsewhere, "b");
    std::vector<std::string> foreign = files;
    foreign[2] = elsewhere.path("b.g1");
    EXPECT_NE(refusal(foreign).find("segment file of shard 1 was made for another plan"),
              std::string::npos)
        << refusal(foreign);
    std::vector<std::string> summary = files;
    summary[2] = dir.path("a.s1");
    EXPECT_NE(refusal(summary).find("is a summary file of shard 1"), std::string::npos);
    // The output may not replace an input.
    EXPECT_NE(errorOf([&] { mergeShards(plan, files, files[1]); }).find("same file as the input"),
              std::string::npos);
    // And the good set merges.
    EXPECT_EQ(errorOf([&] { mergeShards(plan, files, out); }), "");
}

TEST(ShardMerge, AStaleSegmentIsRefused)
{
    ScratchDir dir;
    std::vector<std::string> tiles = everestTiles(dir);
    const BuildOptions options = optionsFor("lossless");
    ShardPlan plan = makePlan(tiles, options, 2, dir.path("plan.json"));
    shardedBuild(plan, dir, "a");
    const std::string old_segment = dir.path("old.g0");
    fs::copy_file(dir.path("a.g0"), old_segment);
    editTile(tiles[0]);
    plan = makePlan(tiles, options, 2, dir.path("plan.json"));
    shardedBuild(plan, dir, "a");
    std::vector<std::string> files = {dir.path("a.top0"), old_segment};
    for (int64_t id = 1; id < int64_t(plan.shards.size()); ++id)
        files.push_back(dir.path("a.g" + std::to_string(id)));
    const std::string message = errorOf([&] { mergeShards(plan, files, dir.path("out.ridge")); });
    EXPECT_NE(message.find("segment of shard 0 was built from other inputs"), std::string::npos)
        << message;
}

} // namespace
} // namespace ridge
