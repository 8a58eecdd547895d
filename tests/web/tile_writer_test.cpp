// `ridge tiles`' library: the same tiles `ridge serve` answers, written to a directory or a
// PMTiles archive, atomically; bad outputs and zooms refused before any work.
#include "ridge/web/tile_writer.h"

#include "everest_web.h"
#include "ridge/core/error.h"
#include "ridge/web/gzip.h"
#include "ridge/web/pmtiles.h"
#include "ridge/web/tile_service.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>

using namespace ridge;
using namespace ridge::web;

using TileWriter = test::EverestArchiveSuite;

TEST_F(TileWriter, DirectoryAndPmtilesHoldWhatTheServerServes)
{
    const test::ScratchDir dir;
    TileService service({archive()}, {});
    const std::string name = service.tilesets()[0]->name();
    TileWriteOptions options;
    options.threads = 2;
    const TileWriteReport d = writeTiles(archive(), dir.path("tiles"), options);
    const TileWriteReport p = writeTiles(archive(), dir.path("tiles.pmtiles"), options);
    EXPECT_EQ(d.tiles, p.tiles);
    EXPECT_EQ(d.max_zoom, service.tilesets()[0]->info().max_zoom);
    const nlohmann::json layer =
        nlohmann::json::parse(test::readFile(dir.path("tiles/layer.json")));
    EXPECT_EQ(layer["tiles"][0], "{z}/{x}/{y}.terrain");
    const PmtilesReader pm(dir.path("tiles.pmtiles"));
    EXPECT_EQ(pm.addressedTiles(), p.tiles);
    EXPECT_EQ(pm.header().tile_compression, PmtilesCompression::Gzip);
    EXPECT_EQ(nlohmann::json::parse(pm.metadata())["ridge:tiling"], "geographic-tms+1");
    uint64_t count = 0;
    for (int z = 0; z <= d.max_zoom; ++z)
        for (const TileRange& r : service.tilesets()[0]->available(z))
            for (int64_t y = r.y0; y <= r.y1; ++y)
                for (int64_t x = r.x0; x <= r.x1; ++x) {
                    WebRequest request;
                    request.path = "/" + name + "/" + std::to_string(z) + "/" + std::to_string(x) +
                                   "/" + std::to_string(y) + ".terrain";
                    request.accept_encoding = "gzip";
                    request.accept = "application/vnd.quantized-mesh;extensions="
                                     "octvertexnormals-watermask-metadata";
                    const WebResponse served = service.handle(request);
                    ASSERT_EQ(served.status, 200);
                    const std::string raw = detail::gzipDecompress(served.body, 1 << 26);
                    const std::string file = test::readFile(
                        dir.path("tiles/" + std::to_string(z) + "/" + std::to_string(x) + "/" +
                                 std::to_string(y) + ".terrain"));
                    EXPECT_EQ(detail::gzipDecompress(file, 1 << 26), raw);
                    const std::optional<std::vector<uint8_t>> stored = pm.tile({z + 1, x, y});
                    ASSERT_TRUE(stored);
                    EXPECT_EQ(detail::gzipDecompress(std::string(stored->begin(), stored->end()),
                                                     1 << 26),
                              raw);
                    ++count;
                }
    EXPECT_EQ(count, d.tiles);
}

TEST_F(TileWriter, TerrainRgbToPmtilesAndDirectory)
{
    const test::ScratchDir dir;
    TileWriteOptions options;
    options.format = TileFormat::TerrariumRgb;
    options.image = ImageFormat::Webp;
    options.min_zoom = 8;
    const TileWriteReport r = writeTiles(archive(), dir.path("rgb.pmtiles"), options);
    EXPECT_EQ(r.min_zoom, 8);
    EXPECT_EQ(r.max_zoom, 10);
    const PmtilesReader pm(dir.path("rgb.pmtiles"));
    EXPECT_EQ(pm.header().tile_type, PmtilesType::Webp);
    EXPECT_EQ(pm.header().min_zoom, 8);
    EXPECT_EQ(nlohmann::json::parse(pm.metadata())["encoding"], "terrarium");
    const std::optional<std::vector<uint8_t>> tile = pm.tile({10, 759, 429});
    ASSERT_TRUE(tile);
    const RgbImage image = decodeRgbImage(ImageFormat::Webp, *tile);
    EXPECT_EQ(image.width, 256);
    // Everest's pixel decodes near its 8,848 m (SRTM's 3″ sample there is about 8,750 m).
    double highest = 0;
    for (size_t i = 0; i < image.rgb.size(); i += 3)
        highest = std::max(highest, decodeRgbHeight(RgbEncoding::Terrarium, &image.rgb[i]));
    EXPECT_GT(highest, 8500.0);
    EXPECT_LT(highest, 8900.0);
    options.format = TileFormat::MapboxRgb;
    options.image = ImageFormat::Png;
    options.size = 512;
    const TileWriteReport d = writeTiles(archive(), dir.path("rgb"), options);
    EXPECT_EQ(d.max_zoom, 9);
    EXPECT_TRUE(std::filesystem::exists(dir.path("rgb/9/379/214.png")));
    EXPECT_EQ(nlohmann::json::parse(test::readFile(dir.path("rgb/tiles.json")))["tiles"][0],
              "{z}/{x}/{y}.png");
}

TEST_F(TileWriter, RefusesBadOutputsAndZoomsAndLeavesNothing)
{
    const test::ScratchDir dir;
    TileWriteOptions options;
    EXPECT_THROW(writeTiles(archive(), archive(), options), Error) << "over the input";
    std::filesystem::create_directory(dir.path("exists"));
    EXPECT_THROW(writeTiles(archive(), dir.path("exists"), options), Error);
    options.max_zoom = 20;
    try {
        writeTiles(archive(), dir.path("deep.pmtiles"), options);
        ADD_FAILURE() << "zoom 20 accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("zoom 0 to 11"), std::string::npos) << e.what();
    }
    options.max_zoom = 3;
    options.min_zoom = 5;
    EXPECT_THROW(writeTiles(archive(), dir.path("z.pmtiles"), options), Error);
    options = {};
    options.size = 300;
    EXPECT_THROW(writeTiles(archive(), dir.path("s"), options), Error);
    // Cancelled half way: no directory, no temporary, no PMTiles file.
    options = {};
    options.progress = [](double fraction) { return fraction < 0.5; };
    EXPECT_THROW(writeTiles(archive(), dir.path("cancelled"), options), Cancelled);
    EXPECT_THROW(writeTiles(archive(), dir.path("cancelled.pmtiles"), options), Cancelled);
    EXPECT_EQ(test::namesIn(dir.dir()), std::vector<std::string>{"exists"});
}
