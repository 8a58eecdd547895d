// The bench driver on the fixture with ridge's lossless codec: every row present and checked,
// the same integer bound for every anchor, and reports that name everything they compare.
#include "ridge/codec/codec_registry.h"
#include "ridge/codecbench/codec_bench.h"
#include "ridge/core/error.h"
#include "ridge/io/raster_source.h"

#include "test_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>

using namespace ridge;
using namespace ridge::codecbench;

namespace {

const std::vector<std::string> kAnchors{"LERC",       "JPEG-LS",    "JPEG 2000",
                                        "JPEG XL e7", "JPEG XL e9", "JPEG XL e9 progressive",
                                        "MED+zstd",   "ZFP"};

const io::ElevationRaster& everest()
{
    static const io::ElevationRaster raster = io::ingestRaster(test::dataPath("everest_crop.tif"));
    return raster;
}

CodecBenchOptions losslessOptions(const test::ScratchDir& dir, std::vector<double> bounds)
{
    CodecBenchOptions options;
    options.max_errors = std::move(bounds);
    options.tile_size = 64;
    options.ridge_codecs = {"lossless"};
    options.scratch_dir = dir.dir().string();
    return options;
}

} // namespace

TEST(CodecBench, LosslessRidgeRowKeepsItsBoundAndEveryAnchorIsReported)
{
    test::ScratchDir dir;
    const CodecBenchReport r = runCodecBench(everest(), losslessOptions(dir, {1.0}));
    ASSERT_EQ(r.bounds.size(), 1u);
    const BoundResult& b = r.bounds[0];
    EXPECT_EQ(b.max_error_codes, 1); // Int16 metres: 1 m per code
    ASSERT_EQ(b.rows.size(), 1 + kAnchors.size());

    const CodecRow& ridge_row = b.rows[0];
    EXPECT_EQ(ridge_row.codec, "ridge lossless");
    EXPECT_EQ(ridge_row.scope, "pyramid");
    EXPECT_TRUE(ridge_row.bound_ok);
    EXPECT_EQ(ridge_row.max_error_codes, 0);
    EXPECT_GT(ridge_row.bytes, 0u);
    // Every level is decoded, so ridge's decoder produces more samples than the finest level.
    EXPECT_GT(ridge_row.decode_bytes, uint64_t(r.width) * r.height * 2);
    EXPECT_GT(ridge_row.decode_seconds, 0.0);
    EXPECT_GT(ridge_row.decode_mb_per_s, 0.0);
    // Lossless: a view reads its selected patches alone.
    ASSERT_EQ(ridge_row.view_bytes.size(), 3u);
    for (const ViewBytesFigure& v : ridge_row.view_bytes) {
        EXPECT_FALSE(v.counts_ancestors) << v.view;
        EXPECT_EQ(v.patches, v.selected) << v.view;
        EXPECT_GT(v.bytes, 0u) << v.view;
        EXPECT_LE(v.bytes, ridge_row.bytes) << v.view;
    }

    for (size_t i = 0; i < kAnchors.size(); ++i) {
        const CodecRow& row = b.rows[1 + i];
        EXPECT_EQ(row.codec, kAnchors[i]);
        EXPECT_EQ(row.scope, "finest level");
        EXPECT_TRUE(row.bound_ok) << row.codec << " max error " << row.max_error_codes;
        EXPECT_LE(row.max_error_codes, 1) << row.codec;
        EXPECT_GT(row.bytes, 0u);
        EXPECT_NEAR(row.ratio, double(r.width) * r.height * 2 / double(row.bytes), 1e-9);
        EXPECT_GT(row.encode_mb_per_s, 0.0);
        EXPECT_GT(row.decode_mb_per_s, 0.0);
        EXPECT_EQ(row.encode_bytes, uint64_t(r.width) * r.height * 2);
        EXPECT_EQ(row.decode_bytes, uint64_t(r.width) * r.height * 2) << row.codec;
        EXPECT_TRUE(row.view_bytes.empty()) << row.codec << ": anchors have no pyramid";
    }
    EXPECT_TRUE(std::filesystem::is_empty(dir.dir())) << "ridge's scratch archive must be removed";
}

TEST(CodecBench, ProgressiveRidgeRowKeepsItsEndToEndBound)
{
    test::ScratchDir dir;
    CodecBenchOptions options = losslessOptions(dir, {1.0, 4.0});
    options.ridge_codecs = {"progressive"};
    const CodecBenchReport r = runCodecBench(everest(), options);
    for (const BoundResult& b : r.bounds) {
        const CodecRow& ridge_row = b.rows.front();
        EXPECT_EQ(ridge_row.codec, "ridge progressive");
        EXPECT_TRUE(ridge_row.bound_ok)
            << b.max_error_metres << " m: " << ridge_row.max_error_metres;
        EXPECT_LE(ridge_row.max_error_metres, b.max_error_metres + 1e-9);
        // Progressive: every view reads its selected patches' ancestors too.
        ASSERT_EQ(ridge_row.view_bytes.size(), 3u);
        for (const ViewBytesFigure& v : ridge_row.view_bytes) {
            EXPECT_TRUE(v.counts_ancestors) << v.view;
            EXPECT_GT(v.patches, v.selected) << v.view;
            EXPECT_LE(v.bytes, ridge_row.bytes) << v.view;
        }
    }
    // A looser bound must not cost more bytes.
    EXPECT_LE(r.bounds[1].rows.front().bytes, r.bounds[0].rows.front().bytes);
}

TEST(CodecBench, EveryRegisteredLossyCodecGetsItsOwnRidgeRowWithinTheBound)
{
    // The rows come from the registry: each lossy codec, built at each bound, before the
    // anchors, in the order asked for.
    test::ScratchDir dir;
    CodecBenchOptions options = losslessOptions(dir, {4.0});
    options.ridge_codecs.clear();
    for (const ridge::CodecInfo& c : codecRegistry())
        if (c.lossy)
            options.ridge_codecs.push_back(c.name);
    ASSERT_GE(options.ridge_codecs.size(), 2u);
    const CodecBenchReport r = runCodecBench(everest(), options);
    ASSERT_EQ(r.bounds.size(), 1u);
    for (size_t k = 0; k < options.ridge_codecs.size(); ++k) {
        const CodecRow& row = r.bounds[0].rows[k];
        EXPECT_EQ(row.codec, "ridge " + options.ridge_codecs[k]);
        EXPECT_EQ(row.scope, "pyramid");
        EXPECT_TRUE(row.bound_ok) << row.codec << ": " << row.max_error_metres;
        EXPECT_LE(row.max_error_metres, 4.0 + 1e-9) << row.codec;
    }
    EXPECT_NE(r.bounds[0].rows[options.ridge_codecs.size()].scope, "pyramid")
        << "the anchors follow";
    options.ridge_codecs = {"progressive", "jpeg2001"};
    EXPECT_THROW(runCodecBench(everest(), options), Error);
}

TEST(CodecBench, AVariantWithoutABoundCodesTheTilesAndReportsItsMeasuredErrors)
{
    // The variants the registry asks codec-bench to compare (the fractal paper's mode): no
    // archive can hold them, so each anchor tile is one patch; max error, RMSE and PSNR are
    // what was measured, never a bound.
    test::ScratchDir dir;
    CodecBenchOptions options = losslessOptions(dir, {4.0});
    options.ridge_codecs.clear();
    for (const ridge::CodecInfo& c : codecRegistry())
        for (const char* v : c.bench_variants)
            options.ridge_codecs.push_back(v);
    ASSERT_FALSE(options.ridge_codecs.empty());
    const CodecBenchReport r = runCodecBench(everest(), options);
    for (size_t k = 0; k < options.ridge_codecs.size(); ++k) {
        const CodecRow& row = r.bounds[0].rows[k];
        EXPECT_FALSE(row.bounded) << row.codec;
        EXPECT_EQ(row.scope, "tiles, no bound");
        EXPECT_GT(row.bytes, 0u);
        EXPECT_GT(row.max_error_metres, 4.0) << row.codec << ": the paper's codec has no bound";
        EXPECT_GT(row.rmse_metres, 0.0);
        EXPECT_TRUE(std::isfinite(row.psnr_db));
        EXPECT_GT(row.violations, 0);
    }
    const std::string table = formatCodecBenchTable(r);
    EXPECT_NE(table.find("none ("), std::string::npos) << table;
    EXPECT_EQ(table.find("VIOLATED"), std::string::npos) << "a mode without a bound violates none";
}

TEST(CodecBench, TableAndJsonNameEveryCodecAndSayWhatRidgeCounts)
{
    test::ScratchDir dir;
    const CodecBenchReport r = runCodecBench(everest(), losslessOptions(dir, {0.5, 4.0}));
    const std::string table = formatCodecBenchTable(r);
    for (const std::string& name : kAnchors)
        EXPECT_NE(table.find(name), std::string::npos) << name;
    EXPECT_NE(table.find("ridge lossless"), std::string::npos);
    EXPECT_NE(table.find("every coarser level"), std::string::npos) << "footnote on ridge's scope";
    EXPECT_EQ(table.find("VIOLATED"), std::string::npos) << table;
    EXPECT_NE(table.find("ridge lossless: bytes fetched per view at 1920×1080, ε = 2 px: near "),
              std::string::npos)
        << table;

    const nlohmann::json j = nlohmann::json::parse(formatCodecBenchJson(r));
    EXPECT_EQ(j["machine"]["threads"], 1);
    EXPECT_EQ(j["tile_size"], 64);
    EXPECT_EQ(j["views"]["width"], 1920);
    EXPECT_EQ(j["views"]["epsilon_px"], 2.0);
    EXPECT_FALSE(j["machine"]["cpu_model"].get<std::string>().empty());
    ASSERT_EQ(j["bounds"].size(), 2u);
    EXPECT_EQ(j["bounds"][0]["max_error_codes"], 0); // 0.5 m < 1 m per code: lossless
    EXPECT_EQ(j["bounds"][1]["max_error_codes"], 4);
    for (const auto& bound : j["bounds"]) {
        std::vector<std::string> codecs;
        for (const auto& row : bound["rows"]) {
            codecs.push_back(row["codec"]);
            EXPECT_TRUE(row["bound_ok"].get<bool>()) << row.dump();
            EXPECT_GT(row["decode_mb_per_s"].get<double>(), 0.0) << row["codec"];
        }
        const auto& views = bound["rows"][0]["view_bytes"];
        for (const char* view : {"near", "mid", "far"})
            EXPECT_GT(views[view]["bytes"].get<uint64_t>(), 0u) << view;
        EXPECT_FALSE(bound["rows"][1].contains("view_bytes"));
        EXPECT_EQ(codecs.front(), "ridge lossless");
        for (const std::string& name : kAnchors)
            EXPECT_NE(std::find(codecs.begin(), codecs.end(), name), codecs.end()) << name;
    }
    for (const auto& row : j["bounds"][0]["rows"])
        EXPECT_TRUE(row["psnr_db"].is_null()) << row["codec"] << " is exact at e = 0";
    size_t libraries = 0;
    for (const auto& c : j["codecs"])
        libraries +=
            c["library"].get<std::string>().find_first_of("0123456789") != std::string::npos;
    EXPECT_EQ(libraries, 1 + kAnchors.size()) << "every library states its version";
}

TEST(CodecBench, WholeGridTileIsOneTilePerAnchor)
{
    test::ScratchDir dir;
    CodecBenchOptions options = losslessOptions(dir, {16.0});
    options.tile_size = 0;
    const CodecBenchReport r = runCodecBench(everest(), options);
    for (const CodecRow& row : r.bounds[0].rows)
        EXPECT_TRUE(row.bound_ok) << row.codec;
}

TEST(CodecBench, InvalidOptionsAreRejectedByName)
{
    test::ScratchDir dir;
    auto messageOf = [&](const CodecBenchOptions& options) {
        try {
            runCodecBench(everest(), options);
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    EXPECT_EQ(messageOf(losslessOptions(dir, {-1.0})),
              "max_errors[0] (metres) is -1: must be a number in (0, 1e+07]");
    EXPECT_EQ(messageOf(losslessOptions(dir, {1.0, std::nan("")})),
              "max_errors[1] (metres) is nan: must be a number in (0, 1e+07]");
    EXPECT_EQ(messageOf(losslessOptions(dir, {})), "max_errors: at least one bound is needed");
    CodecBenchOptions options = losslessOptions(dir, {1.0});
    options.tile_size = -5;
    EXPECT_EQ(messageOf(options), "tile_size is -5: must be an integer in [0, 65536]");
    options = losslessOptions(dir, {1.0});
    options.view_width = 0;
    EXPECT_EQ(messageOf(options), "view_width is 0: must be an integer in [1, 65536]");
}

TEST(CodecBench, MissingInputIsAnErrorNamingTheFile)
{
    test::ScratchDir dir;
    const std::string missing = dir.path("no-such-dem.tif");
    try {
        runCodecBench(missing, losslessOptions(dir, {1.0}));
        FAIL();
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find(missing), std::string::npos) << e.what();
    }
}

TEST(CodecBench, PlotIsAPng)
{
    test::ScratchDir dir;
    const CodecBenchReport r = runCodecBench(everest(), losslessOptions(dir, {1.0, 4.0}));
    const std::string png = dir.path("plot.png");
    writeCodecBenchPlot(r, png);
    std::ifstream in(png, std::ios::binary);
    char magic[8] = {};
    in.read(magic, 8);
    EXPECT_EQ(std::string(magic + 1, 3), "PNG");
    EXPECT_GT(std::filesystem::file_size(png), 10000u);
}

TEST(CodecBench, OverviewRowsCodeEveryOverviewDownToTheMinimumSize)
{
    // everest_crop is 301 x 203: with a 64-sample minimum, overviews of every 2nd, 4th and
    // 8th sample (151 x 102, 76 x 51, 38 x 26): the last is the first within 64 a side.
    test::ScratchDir dir;
    CodecBenchOptions options = losslessOptions(dir, {4.0});
    options.overviews = true;
    options.overview_min_size = 64;
    const CodecBenchReport r = runCodecBench(everest(), options);
    const std::vector<std::pair<int, int>> sizes{{151, 102}, {76, 51}, {38, 26}};
    EXPECT_EQ(r.overview_sizes, sizes);
    uint64_t samples = uint64_t(r.width) * r.height;
    for (const auto& [w, h] : sizes)
        samples += uint64_t(w) * h;

    const BoundResult& b = r.bounds[0];
    // Every anchor but the one whose stream is a pyramid already gets a second row.
    std::vector<size_t> single_level;
    for (size_t k = 0; k < kAnchors.size(); ++k)
        if (kAnchors[k] != "JPEG XL e9 progressive")
            single_level.push_back(k);
    ASSERT_EQ(single_level.size(), kAnchors.size() - 1);
    ASSERT_EQ(b.rows.size(), 1 + kAnchors.size() + single_level.size());
    for (size_t i = 0; i < single_level.size(); ++i) {
        const size_t k = single_level[i];
        const CodecRow& finest = b.rows[1 + k];
        const CodecRow& pyramid = b.rows[1 + kAnchors.size() + i];
        EXPECT_EQ(finest.codec, kAnchors[k]);
        EXPECT_EQ(finest.scope, "finest level");
        EXPECT_EQ(pyramid.codec, kAnchors[k] + " + overviews");
        EXPECT_EQ(pyramid.scope, "with overviews");
        // Every level was coded and decoded, and each costs something.
        EXPECT_EQ(pyramid.decode_bytes, samples * 2) << pyramid.codec;
        EXPECT_EQ(pyramid.encode_bytes, samples * 2) << pyramid.codec;
        EXPECT_GT(pyramid.bytes, finest.bytes) << pyramid.codec;
        if (finest.bound_ok) {
            EXPECT_TRUE(pyramid.bound_ok) << pyramid.codec;
        }
        // The ratio stays the finest level's samples over the bytes, like ridge's row.
        EXPECT_NEAR(pyramid.ratio, double(r.width) * r.height * 2 / double(pyramid.bytes), 1e-9);
    }
    const std::string table = formatCodecBenchTable(r);
    EXPECT_NE(table.find("JPEG XL e9 + overviews"), std::string::npos);
    EXPECT_NE(table.find("151 x 102, 76 x 51, 38 x 26"), std::string::npos) << table;
    const auto j = nlohmann::json::parse(formatCodecBenchJson(r));
    EXPECT_EQ(j["overview_sizes"].size(), 3u);
    EXPECT_EQ(j["codecs"].size(), 1 + kAnchors.size() + single_level.size());
}

TEST(CodecBench, NoOverviewRowsUnlessAskedAndTheMinimumSizeIsChecked)
{
    test::ScratchDir dir;
    const CodecBenchReport r = runCodecBench(everest(), losslessOptions(dir, {16.0}));
    EXPECT_TRUE(r.overview_sizes.empty());
    for (const CodecRow& row : r.bounds[0].rows)
        EXPECT_EQ(row.codec.find("overviews"), std::string::npos) << row.codec;

    CodecBenchOptions options = losslessOptions(dir, {16.0});
    options.overviews = true;
    options.overview_min_size = 0;
    try {
        runCodecBench(everest(), options);
        FAIL() << "overview_min_size 0 accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("overview_min_size"), std::string::npos) << e.what();
    }
}
