// Terrain-RGB tiles: the two encodings bit for bit, the vertical step rule (no terraces on
// gentle slopes), lossless images, and tiles within their stated step of the archive.
#include "ridge/web/terrain_rgb.h"

#include "everest_web.h"
#include "ridge/core/error.h"
#include "ridge/web/tile_sampler.h"
#include "ridge/web/tile_service.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <random>

using namespace ridge;
using namespace ridge::web;

TEST(TerrainRgb, EncodesBothSchemesBitForBit)
{
    // Worked from the encodings' definitions: Mapbox 0 m is code 100000 = 0x0186A0,
    // Terrarium 0 m is 32768 · 256 = 0x800000.
    EXPECT_EQ(encodeRgbHeight(RgbEncoding::Mapbox, 0.0, 0.1),
              (std::array<uint8_t, 3>{1, 134, 160}));
    EXPECT_EQ(encodeRgbHeight(RgbEncoding::Terrarium, 0.0, 1.0 / 256),
              (std::array<uint8_t, 3>{128, 0, 0}));
    // Everest, 8848.86 m: Mapbox 188488.6 → 188489 = 0x02E049; Terrarium 41616.86 · 256.
    EXPECT_EQ(encodeRgbHeight(RgbEncoding::Mapbox, 8848.86, 0.1),
              (std::array<uint8_t, 3>{0x02, 0xE0, 0x49}));
    const uint32_t t = uint32_t(std::lround((8848.86 + 32768.0) * 256.0));
    EXPECT_EQ(encodeRgbHeight(RgbEncoding::Terrarium, 8848.86, 1.0 / 256),
              (std::array<uint8_t, 3>{uint8_t(t >> 16), uint8_t(t >> 8), uint8_t(t)}));
    // Out of range: clamped to the encodings' ends, not wrapped.
    const auto low = encodeRgbHeight(RgbEncoding::Mapbox, -20000.0, 0.1);
    EXPECT_EQ(decodeRgbHeight(RgbEncoding::Mapbox, low.data()), -10000.0);
    const auto high = encodeRgbHeight(RgbEncoding::Terrarium, 40000.0, 1.0 / 256);
    EXPECT_NEAR(decodeRgbHeight(RgbEncoding::Terrarium, high.data()), 32768.0 - 1.0 / 256, 1e-9);
    // Round trips within half a step, at every step the rule can choose.
    std::mt19937 random(7);
    std::uniform_real_distribution<double> height(-9000.0, 9000.0);
    for (const RgbEncoding e : {RgbEncoding::Mapbox, RgbEncoding::Terrarium})
        for (int k = 0; k <= 8; ++k) {
            const double step = nativeStep(e) * double(1 << k);
            for (int i = 0; i < 1000; ++i) {
                const double h = height(random);
                const auto rgb = encodeRgbHeight(e, h, step);
                EXPECT_LE(std::abs(decodeRgbHeight(e, rgb.data()) - h), step / 2 + 1e-9);
            }
        }
}

TEST(TerrainRgb, TheStepRuleLeavesNoTerracesOnGentleSlopes)
{
    // The rule's figures: 38 m pixels (zoom 12) keep the native steps; 4.9 km pixels (zoom 5)
    // over a 10 m archive bound round to 3.2 m (Mapbox) and 4 m (Terrarium).
    EXPECT_EQ(rgbStep(RgbEncoding::Mapbox, 38.2, 0.0), 0.1);
    EXPECT_EQ(rgbStep(RgbEncoding::Terrarium, 38.2, 5.0), 1.0 / 32);
    EXPECT_EQ(rgbStep(RgbEncoding::Mapbox, 4892.0, 10.0), 3.2);
    EXPECT_EQ(rgbStep(RgbEncoding::Terrarium, 4892.0, 10.0), 4.0);
    EXPECT_EQ(rgbStep(RgbEncoding::Terrarium, 4892.0, 1.0), 1.0) << "within the archive's bound";
    // A 0.1 % ramp (a river plain) at every zoom: each pixel decodes higher than the last —
    // no plateau, so no terrace in a hillshade.
    for (const RgbEncoding e : {RgbEncoding::Mapbox, RgbEncoding::Terrarium})
        for (int z = 0; z <= 14; ++z) {
            const double pixel = WebMercatorXyz::metresPerPixel(z, 0.0, 256);
            if (pixel / 1000.0 < nativeStep(e))
                continue; // finer than the encoding: its own step decides, not the rule
            const double step = rgbStep(e, pixel, 1e9);
            double last = -INFINITY;
            // Within both encodings' range (Terrarium's ends at 32,768 m).
            for (int i = 0; i < 256 && 0.001 * pixel * i < 30000.0; ++i) {
                const auto rgb = encodeRgbHeight(e, 100.0 + 0.001 * pixel * i, step);
                const double h = decodeRgbHeight(e, rgb.data());
                EXPECT_GT(h, last) << rgbEncodingName(e) << " zoom " << z << " pixel " << i;
                last = h;
            }
        }
}

TEST(TerrainRgb, ImagesAreLossless)
{
    std::mt19937 random(3);
    std::vector<uint8_t> rgb(37 * 23 * 3);
    for (uint8_t& b : rgb)
        b = uint8_t(random());
    for (const ImageFormat f : {ImageFormat::Png, ImageFormat::Webp}) {
        const std::vector<uint8_t> bytes = encodeRgbImage(f, rgb, 37, 23);
        const RgbImage back = decodeRgbImage(f, bytes);
        EXPECT_EQ(back.width, 37);
        EXPECT_EQ(back.height, 23);
        EXPECT_EQ(back.rgb, rgb) << imageFormatName(f);
        EXPECT_THROW(decodeRgbImage(f, std::span(bytes).first(bytes.size() / 2)), Error);
        EXPECT_THROW(decodeRgbImage(f, std::vector<uint8_t>(64, 0x42)), Error);
    }
    EXPECT_THROW(encodeRgbImage(ImageFormat::Png, rgb, 37, 24), Error) << "wrong size";
    EXPECT_THROW(encodeRgbImage(ImageFormat::Webp, rgb, 0, 23), Error);
}

using TerrainRgbTiles = test::EverestArchiveSuite;

TEST_F(TerrainRgbTiles, PixelsDecodeWithinTheStatedStepOfTheArchive)
{
    TileSampler sampler(archive());
    HeightQuery query(archive());
    for (const RgbEncoding e : {RgbEncoding::Mapbox, RgbEncoding::Terrarium})
        for (const int z : {9, 12, sampler.maxMercatorZoom(256)}) {
            const TileKey k{z, int64_t(std::floor((86.925 + 180.0) / 360.0 * double(1 << z))), 0};
            // The row of the tile holding Everest's latitude.
            TileKey key = k;
            for (int64_t y = 0; y < (int64_t(1) << z); ++y)
                if (const GeoRect r = WebMercatorXyz::rect({z, k.x, y});
                    r.south <= 27.988 && r.north >= 27.988)
                    key.y = y;
            const std::optional<RgbTile> tile =
                makeRgbTile(sampler, key, 256, e, ImageFormat::Webp);
            ASSERT_TRUE(tile);
            const RgbImage image = decodeRgbImage(ImageFormat::Webp, tile->image);
            ASSERT_EQ(image.width, 256);
            double worst = 0.0;
            size_t checked = 0;
            for (int j = 0; j < 256; ++j)
                for (int i = 0; i < 256; ++i) {
                    const glm::dvec2 ll(WebMercatorXyz::longitude(key, i, 256),
                                        WebMercatorXyz::latitude(key, j, 256));
                    const HeightSample s = query.sample(ll, PointSpace::LonLat, tile->level);
                    if (!s.on_raster || s.nodata)
                        continue;
                    const double h =
                        decodeRgbHeight(e, &image.rgb[(size_t(j) * 256 + size_t(i)) * 3]);
                    worst = std::max(worst, std::abs(h - s.height));
                    ++checked;
                }
            std::printf("%s zoom %d: level %d, step %.4f m, %zu pixels on the archive, worst "
                        "%.4f m from the level's surface\n",
                        rgbEncodingName(e), z, tile->level, tile->step, checked, worst);
            EXPECT_GT(checked, 0u);
            // float heights in between: a few micrometres on 9 km.
            EXPECT_LE(worst, tile->step / 2 + 1e-3) << rgbEncodingName(e) << " zoom " << z;
        }
}

TEST_F(TerrainRgbTiles, ServedWithTileJsonAndStatedStep)
{
    TileService s({archive()}, {});
    const std::string name = s.tilesets()[0]->name();
    WebRequest tilejson;
    tilejson.path = "/" + name + "/terrarium@2x.json";
    tilejson.query = "format=webp";
    const WebResponse j = s.handle(tilejson);
    ASSERT_EQ(j.status, 200) << j.body;
    const nlohmann::json doc = nlohmann::json::parse(j.body);
    EXPECT_EQ(doc["encoding"], "terrarium");
    EXPECT_EQ(doc["tileSize"], 512);
    const std::string tiles = doc["tiles"][0];
    EXPECT_EQ(tiles.rfind("terrarium@2x/{z}/{x}/{y}.webp?v=", 0), 0u) << tiles;
    // 512 px tiles stop a zoom before 256 px ones: the same pixels.
    const int max_zoom = s.tilesets()[0]->rgbMaxZoom(256);
    EXPECT_EQ(doc["maxzoom"], max_zoom - 1);
    EXPECT_EQ(max_zoom, 10) << "3\" samples: 10's pixels are 134 m at 28°N, 11's 67 m";

    const TileKey k = {10, 759, 429}; // holds Everest (86.925°E, 27.988°N)
    const GeoRect r = WebMercatorXyz::rect(k);
    ASSERT_TRUE(r.west <= 86.925 && r.east >= 86.925 && r.south <= 27.988 && r.north >= 27.988);
    WebRequest get;
    get.path = "/" + name + "/mapbox/10/759/429.png";
    const WebResponse tile = s.handle(get);
    ASSERT_EQ(tile.status, 200) << tile.body;
    EXPECT_EQ(tile.content_type, "image/png");
    EXPECT_EQ(tile.header("Content-Encoding"), nullptr);
    EXPECT_NE(tile.header("X-Ridge-Step"), nullptr);
    EXPECT_NE(tile.header("ETag"), nullptr);
    const RgbImage image = decodeRgbImage(
        ImageFormat::Png,
        std::span(reinterpret_cast<const uint8_t*>(tile.body.data()), tile.body.size()));
    EXPECT_EQ(image.width, 256);
    get.if_none_match = *tile.header("ETag");
    EXPECT_EQ(s.handle(get).status, 304);

    for (const std::string& bad :
         std::vector<std::string>{"/mapbox/10/759/429.jpg", "/mapbox/10/759/a.png"}) {
        get.path = "/" + name + bad;
        get.if_none_match.clear();
        EXPECT_EQ(s.handle(get).status, 400) << bad;
    }
    for (const std::string& absent :
         std::vector<std::string>{"/mapbox/10/0/0.png", "/mapbox/10/2000/429.png",
                                  "/mapbox/29/0/0.png", "/blue/10/759/429.png", "/mapbox.png",
                                  "/mapbox/" + std::to_string(max_zoom + 3) + "/0/0.webp"}) {
        get.path = "/" + name + absent;
        EXPECT_EQ(s.handle(get).status, 404) << absent;
    }
}
