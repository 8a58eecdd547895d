// What `ridge serve` answers, without sockets: layer.json, tiles within their stated error
// of the archive's finest samples, shared edges, HTTP semantics (status codes, validators,
// compression, caching) and an archive replaced while served.
#include "ridge/web/tile_service.h"

#include "everest_web.h"
#include "ridge/io/geoid_model.h"
#include "ridge/pipeline/build.h"
#include "ridge/web/gzip.h"
#include "ridge/web/tile_sampler.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <thread>

using namespace ridge;
using namespace ridge::web;

namespace {

constexpr const char* kAllExtensions =
    "application/vnd.quantized-mesh;extensions=octvertexnormals-watermask-metadata,"
    "application/octet-stream;q=0.9,*/*;q=0.01";

using TileServiceTest = test::EverestArchiveSuite;

WebResponse get(TileService& s, const std::string& path, const std::string& accept = kAllExtensions,
                const std::string& encoding = "gzip, deflate", const std::string& etag = "")
{
    WebRequest r;
    r.path = path;
    r.accept = accept;
    r.accept_encoding = encoding;
    r.if_none_match = etag;
    return s.handle(r);
}

std::string tilePath(const std::string& set, TileKey k)
{
    return "/" + set + "/" + std::to_string(k.z) + "/" + std::to_string(k.x) + "/" +
           std::to_string(k.y) + ".terrain";
}

QuantizedMesh decodeBody(const WebResponse& r)
{
    const std::string raw =
        r.header("Content-Encoding") ? detail::gzipDecompress(r.body, 1 << 26) : r.body;
    return decodeQuantizedMesh(std::span(reinterpret_cast<const uint8_t*>(raw.data()), raw.size()));
}

} // namespace

TEST_F(TileServiceTest, LayerJsonDescribesTheArchive)
{
    TileService s({archive()}, {});
    ASSERT_EQ(s.tilesets().size(), 1u);
    const std::string name = s.tilesets()[0]->name();
    const WebResponse r = get(s, "/" + name + "/layer.json");
    ASSERT_EQ(r.status, 200) << r.body;
    EXPECT_EQ(r.content_type, "application/json");
    const nlohmann::json layer = nlohmann::json::parse(r.body);
    EXPECT_EQ(layer["format"], "quantized-mesh-1.0");
    EXPECT_EQ(layer["scheme"], "tms");
    EXPECT_EQ(layer["projection"], "EPSG:4326");
    EXPECT_EQ(layer["tiles"][0], "{z}/{x}/{y}.terrain?v={version}");
    const int max_zoom = layer["maxzoom"];
    TileSampler sampler(archive());
    EXPECT_EQ(max_zoom, sampler.maxZoom(64));
    // Both roots at zoom 0; at every zoom the tile over Everest.
    ASSERT_EQ(layer["available"].size(), size_t(max_zoom + 1));
    EXPECT_EQ(layer["available"][0][0]["endX"], 1);
    for (int z = 1; z <= max_zoom; ++z) {
        const TileKey k = GeographicTms::tileAt(z, 86.925, 27.988);
        bool found = false;
        for (const auto& range : layer["available"][size_t(z)])
            found |= k.x >= range["startX"] && k.x <= range["endX"] && k.y >= range["startY"] &&
                     k.y <= range["endY"];
        EXPECT_TRUE(found) << "zoom " << z;
    }
    EXPECT_EQ(layer["ridge"]["verticalReference"], sampler.verticalReference());
    EXPECT_EQ(*r.header("Cache-Control"), "no-cache");
    EXPECT_EQ(*r.header("Access-Control-Allow-Origin"), "*");
}

TEST_F(TileServiceTest, TilesKeepTheirStatedErrorOfTheFinestSamples)
{
    TileService s({archive()}, {});
    const std::string name = s.tilesets()[0]->name();
    HeightQuery finest(archive());
    const int max_zoom = s.tilesets()[0]->info().max_zoom;
    for (int z = 9; z <= max_zoom; ++z) {
        const TileKey k = GeographicTms::tileAt(z, 86.925, 27.988);
        const WebResponse r = get(s, tilePath(name, k));
        ASSERT_EQ(r.status, 200) << r.body;
        EXPECT_EQ(*r.header("Content-Encoding"), "gzip");
        EXPECT_EQ(r.content_type,
                  "application/vnd.quantized-mesh;extensions=octvertexnormals-watermask-metadata");
        const QuantizedMesh m = decodeBody(r);
        EXPECT_EQ(m.oct_normals.size(), 2 * m.vertexCount());
        EXPECT_TRUE(m.water_mask.size() == 1 || m.water_mask.size() == 65536);
        const double claimed = std::stod(*r.header("X-Ridge-Claimed-Error"));
        const double measured = test::everestMeshError(m, k, finest);
        std::printf("zoom %d: %zu vertices, client error %.2f m, claimed %.2f m, measured by "
                    "the test %.2f m\n",
                    z, m.vertexCount(), GeographicTms::geometricError(z), claimed, measured);
        EXPECT_LE(measured, claimed + 1e-3) << "zoom " << z;
        // Lossless: the claim keeps to the client's error (tile_sampler.h, on the samples).
        EXPECT_LE(claimed, GeographicTms::geometricError(z) + 1e-3) << "zoom " << z;
        // The metadata names the available children.
        const nlohmann::json meta = nlohmann::json::parse(m.metadata);
        if (z < max_zoom)
            EXPECT_FALSE(meta["available"][0].empty()) << "zoom " << z;
        else
            EXPECT_FALSE(meta.contains("available"));
    }
}

TEST_F(TileServiceTest, NeighboursShareTheirEdgeVertices)
{
    // Every available pair of neighbours at every zoom from 5: the same vertices along the
    // shared edge, heights within the two tiles' quantization steps. (Tiles of one zoom that
    // read different archive levels broke this at zoom 10, 10/1517/670 and 10/1518/670.)
    TileService s({archive()}, {});
    const std::string name = s.tilesets()[0]->name();
    Tileset& set = *s.tilesets()[0];
    int pairs = 0;
    for (int z = 5; z <= set.info().max_zoom; ++z) {
        const std::vector<TileRange> ranges = set.available(z);
        ASSERT_EQ(ranges.size(), 1u);
        const TileRange& r = ranges[0];
        for (int64_t y = r.y0; y <= r.y1; ++y)
            for (int64_t x = r.x0; x <= r.x1; ++x)
                for (const TileKey b : {TileKey{z, x + 1, y}, TileKey{z, x, y + 1}}) {
                    if (!r.contains(b.x, b.y))
                        continue;
                    const TileKey a{z, x, y};
                    const QuantizedMesh ma = decodeBody(get(s, tilePath(name, a)));
                    const QuantizedMesh mb = decodeBody(get(s, tilePath(name, b)));
                    const bool east = b.x != a.x;
                    const std::vector<uint32_t>& ea = east ? ma.east : ma.north;
                    const std::vector<uint32_t>& eb = east ? mb.west : mb.south;
                    ASSERT_EQ(ea.size(), eb.size()) << z << "/" << x << "/" << y;
                    const double step =
                        (ma.max_height - ma.min_height + mb.max_height - mb.min_height) /
                        QuantizedMesh::kMaxCoordinate / 2.0;
                    for (size_t i = 0; i < ea.size(); ++i) {
                        EXPECT_EQ(east ? ma.v[ea[i]] : ma.u[ea[i]],
                                  east ? mb.v[eb[i]] : mb.u[eb[i]]);
                        EXPECT_NEAR(decodedHeight(ma, ea[i]), decodedHeight(mb, eb[i]),
                                    step + 1e-6);
                    }
                    ++pairs;
                }
    }
    EXPECT_GE(pairs, 15);
}

TEST_F(TileServiceTest, AnswersHttpSemantics)
{
    TileService s({archive()}, {});
    const std::string name = s.tilesets()[0]->name();
    const TileKey k = GeographicTms::tileAt(10, 86.925, 27.988);
    const WebResponse first = get(s, tilePath(name, k));
    ASSERT_EQ(first.status, 200);
    const std::string etag = *first.header("ETag");
    // Revalidation: 304 with the same tag and no body; another tag gets the tile.
    const WebResponse again = get(s, tilePath(name, k), kAllExtensions, "gzip", etag);
    EXPECT_EQ(again.status, 304);
    EXPECT_TRUE(again.body.empty());
    EXPECT_EQ(get(s, tilePath(name, k), kAllExtensions, "gzip", "\"other\"").status, 200);
    EXPECT_EQ(get(s, tilePath(name, k), kAllExtensions, "gzip", "*").status, 304);
    // Without gzip: the same tile, not compressed, under its own tag.
    const WebResponse plain = get(s, tilePath(name, k), kAllExtensions, "identity");
    EXPECT_EQ(plain.header("Content-Encoding"), nullptr);
    EXPECT_EQ(plain.body, detail::gzipDecompress(first.body, 1 << 26));
    EXPECT_NE(*plain.header("ETag"), etag);
    EXPECT_EQ(get(s, tilePath(name, k), kAllExtensions, "gzip;q=0").header("Content-Encoding"),
              nullptr);
    // No extensions asked: none sent.
    const QuantizedMesh bare = decodeBody(get(s, tilePath(name, k), "*/*"));
    EXPECT_TRUE(bare.oct_normals.empty() && bare.water_mask.empty() && bare.metadata.empty());
    // The versioned URL is immutable, others revalidate.
    const std::string version = s.tilesets()[0]->info().version;
    WebRequest pinned;
    pinned.path = tilePath(name, k);
    pinned.query = "v=" + version;
    EXPECT_EQ(*s.handle(pinned).header("Cache-Control"), "public, max-age=86400, immutable");
    EXPECT_EQ(*first.header("Cache-Control"), "no-cache");
    // HEAD: the headers and the length, no body.
    WebRequest head;
    head.method = "HEAD";
    head.path = tilePath(name, k);
    head.accept = kAllExtensions;
    head.accept_encoding = "gzip";
    const WebResponse h = s.handle(head);
    EXPECT_EQ(h.status, 200);
    EXPECT_TRUE(h.body.empty());
    EXPECT_EQ(h.content_length, first.body.size());
    // Each tile made once, then from the cache.
    EXPECT_EQ(s.stats().tiles_made, 2u); // with and without extensions
}

TEST_F(TileServiceTest, RefusesMalformedAndAbsentRequests)
{
    TileService s({archive()}, {});
    const std::string name = s.tilesets()[0]->name();
    for (const std::string& path : std::vector<std::string>{
             "", "layer.json", "/" + name + "/../layer.json", "/" + name + "//layer.json",
             "/" + name + "/a/b/c.terrain", "/" + name + "/1/-1/0.terrain",
             "/" + name + "/1/0/0x1.terrain", "/" + name + "/99999999999999999999/0/0.terrain",
             "/" + name + "/1/ 0/0.terrain", "/" + name + "/1/0/0.terrain\n", "/%2e%2e/etc/passwd",
             "/" + name + std::string("/1/0/\0.terrain", 14), std::string(2000, '/')})
        EXPECT_EQ(get(s, path).status, 400) << path;
    for (const std::string& path : std::vector<std::string>{
             "/nope/layer.json", "/" + name + "/29/0/0.terrain", "/" + name + "/0/2/0.terrain",
             "/" + name + "/1/0/0.terrain", "/" + name + "/5/0/0.terrain",
             "/" + name + "/" + std::to_string(s.tilesets()[0]->info().max_zoom + 1) +
                 "/0/0.terrain",
             "/" + name + "/1/0/0.png", "/index.html"})
        EXPECT_EQ(get(s, path).status, 404) << path;
    WebRequest post;
    post.method = "POST";
    post.path = "/" + name + "/layer.json";
    const WebResponse r = s.handle(post);
    EXPECT_EQ(r.status, 405);
    EXPECT_EQ(*r.header("Allow"), "GET, HEAD, OPTIONS");
    // A root tile the archive misses is the ellipsoid, so Cesium has both roots: at 0 m, with
    // the vertices its curvature needs.
    const QuantizedMesh west = decodeBody(get(s, "/" + name + "/0/0/0.terrain"));
    EXPECT_GT(west.vertexCount(), 16u);
    EXPECT_EQ(west.max_height, 0.f);
    EXPECT_EQ(west.min_height, 0.f);
}

TEST_F(TileServiceTest, ConcurrentRequestsMakeEachTileOnce)
{
    TileServiceOptions options;
    options.tileset.samplers = 3;
    TileService s({archive()}, options);
    const std::string name = s.tilesets()[0]->name();
    const int z = s.tilesets()[0]->info().max_zoom;
    const TileKey centre = GeographicTms::tileAt(z, 86.88, 27.9); // the middle of 3 × 3
    std::vector<TileKey> keys;
    for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
            keys.push_back({z, centre.x + dx, centre.y + dy});
    std::vector<std::vector<std::string>> bodies(8);
    std::vector<std::thread> threads;
    for (size_t t = 0; t < bodies.size(); ++t)
        threads.emplace_back([&, t] {
            for (const TileKey& k : keys) {
                const WebResponse r = get(s, tilePath(name, k));
                bodies[t].push_back(std::to_string(r.status) + r.body);
            }
        });
    for (auto& t : threads)
        t.join();
    for (size_t t = 1; t < bodies.size(); ++t)
        EXPECT_EQ(bodies[t], bodies[0]);
    EXPECT_EQ(s.stats().tiles_made, keys.size());
    EXPECT_EQ(s.stats().cache_hits + s.stats().joined, keys.size() * (bodies.size() - 1));
}

TEST_F(TileServiceTest, AReplacedArchiveIsServedAnewAndACorruptOneIsRefused)
{
    const test::ScratchDir dir;
    const std::string served = dir.path("served.ridge");
    std::filesystem::copy_file(archive(), served);
    TileService s({served}, {});
    const std::string name = s.tilesets()[0]->name();
    const std::string before = s.tilesets()[0]->info().version;
    const TileKey k = GeographicTms::tileAt(11, 86.925, 27.988);
    const WebResponse old_tile = get(s, tilePath(name, k));
    ASSERT_EQ(old_tile.status, 200);

    // Another archive renamed over the path: a new version, its own tiles.
    const std::string other = test::buildEverestArchive(dir, "progressive", 33, 8.0);
    std::filesystem::rename(other, dir.path("next.ridge"));
    std::filesystem::rename(dir.path("next.ridge"), served);
    const std::string after = s.tilesets()[0]->info().version;
    EXPECT_NE(after, before);
    const WebResponse new_tile = get(s, tilePath(name, k));
    ASSERT_EQ(new_tile.status, 200);
    EXPECT_NE(*new_tile.header("ETag"), *old_tile.header("ETag"));
    EXPECT_NE(new_tile.body, old_tile.body);
    EXPECT_GT(std::stod(*new_tile.header("X-Ridge-Claimed-Error")), 0.0) << "lossy archive";

    // Overwritten in place with other bytes: it cannot be reopened, and what the open handle
    // reads fails its checksums, so tiles not yet made are refused (500), never sent corrupt.
    {
        const std::uintmax_t size = std::filesystem::file_size(served);
        std::fstream f(served, std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(std::streamoff(size / 4));
        const std::string junk(size_t(size / 2), '\x5a');
        f.write(junk.data(), std::streamsize(junk.size()));
    }
    int refused = 0, served_ok = 0;
    for (int z = 9; z <= s.tilesets()[0]->info().max_zoom; ++z)
        for (const TileRange& range : s.tilesets()[0]->available(z))
            for (int64_t y = range.y0; y <= range.y1; ++y)
                for (int64_t x = range.x0; x <= range.x1; ++x) {
                    if (TileKey{z, x, y} == k)
                        continue;
                    const WebResponse r = get(s, tilePath(name, {z, x, y}));
                    if (r.status == 500)
                        ++refused;
                    else if (r.status == 200)
                        ++served_ok;
                    else
                        ADD_FAILURE() << r.status;
                }
    EXPECT_GT(refused, 0);
    // Served meanwhile: only tiles whose patches were still cached decoded — never bad bytes
    // (a decoded patch passed its checksum when it was read).
    std::printf("after the overwrite: %d tiles refused, %d made from patches decoded before\n",
                refused, served_ok);
    EXPECT_EQ(get(s, "/" + name + "/layer.json").status, 200);
}

TEST(TileServiceHeights, GeoidHeightsAreServedAboveTheEllipsoid)
{
    // The fixture's heights named as EGM96 height and kept so (no shift at build).
    const test::ScratchDir dir;
    BuildOptions options;
    options.patch_size = 33;
    options.progress = {};
    options.ingest.vertical_datum = "EPSG:5773";
    options.ingest.vertical_shift = io::VerticalShift::None;
    const std::string path = dir.path("egm96.ridge");
    buildArchive(test::dataPath("everest_crop.tif"), path, options);

    TileServiceOptions as_stored;
    as_stored.tileset.ellipsoidal = false;
    TileService archive_heights({path}, as_stored);
    TileService ellipsoid({path}, {});
    const Tileset::Info info = ellipsoid.tilesets()[0]->info();
    EXPECT_EQ(info.heights, "ellipsoid");
    EXPECT_NE(info.conversion.find("EGM96"), std::string::npos) << info.conversion;
    EXPECT_EQ(archive_heights.tilesets()[0]->info().heights, "EGM96 height");
    const nlohmann::json layer = nlohmann::json::parse(get(ellipsoid, "/egm96/layer.json").body);
    EXPECT_NE(layer["ridge"]["heights"].get<std::string>().find("converted from EGM96"),
              std::string::npos);

    // Every vertex of the converted tile stands N higher than the archive's (EGM96's N is
    // about −28 m under Everest), within the two tiles' quantization steps.
    const io::GeoidModel geoid("test", 5773, "EGM96 height");
    const TileKey k = GeographicTms::tileAt(11, 86.88, 27.9);
    const std::string p = tilePath("egm96", k);
    const QuantizedMesh h = decodeBody(get(ellipsoid, p));
    const QuantizedMesh H = decodeBody(get(archive_heights, p));
    ASSERT_EQ(h.vertexCount(), H.vertexCount());
    ASSERT_EQ(h.u, H.u);
    const GeoRect r = GeographicTms::rect(k);
    const double steps = (h.max_height - h.min_height + H.max_height - H.min_height) / 32767.0;
    for (uint32_t i = 0; i < h.vertexCount(); ++i) {
        const std::array<double, 2> ll = {r.west + (r.east - r.west) * h.u[i] / 32767.0,
                                          r.south + (r.north - r.south) * h.v[i] / 32767.0};
        double n = 0;
        geoid.undulations(std::span(&ll, 1), std::span(&n, 1));
        EXPECT_LT(n, -20.0);
        EXPECT_NEAR(decodedHeight(h, i) - decodedHeight(H, i), n, steps + 1e-3) << i;
    }
}
