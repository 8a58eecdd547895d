// PMTiles v3: tile ids along the Hilbert curve (the spec's own examples), archives written and
// read back with run lengths, deduplication and leaf directories, and hostile files refused.
#include "ridge/web/pmtiles.h"

#include "ridge/core/atomic_output.h"
#include "ridge/core/error.h"
#include "test_support.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fstream>

using namespace ridge;
using namespace ridge::web;

namespace {

std::vector<uint8_t> bytesOf(const std::string& s)
{
    return std::vector<uint8_t>(s.begin(), s.end());
}

// Writes `tiles` (in id order) and returns the path.
std::string writeArchive(const test::ScratchDir& dir, const std::string& name,
                         const std::vector<std::pair<TileKey, std::string>>& tiles,
                         const PmtilesHeader& header = {})
{
    const std::string path = dir.path(name);
    AtomicOutput out(path);
    PmtilesWriter writer(out.fd(), path);
    for (const auto& [k, bytes] : tiles)
        writer.add(pmtilesTileId(k), bytesOf(bytes));
    writer.finish(header, R"({"name":"test"})");
    out.commit();
    return path;
}

} // namespace

TEST(Pmtiles, TileIdsFollowTheSpec)
{
    // spec/v3: zoom 0 is id 0; zoom 1's tiles 1..4 along the Hilbert curve.
    EXPECT_EQ(pmtilesTileId({0, 0, 0}), 0u);
    EXPECT_EQ(pmtilesTileId({1, 0, 0}), 1u);
    EXPECT_EQ(pmtilesTileId({1, 0, 1}), 2u);
    EXPECT_EQ(pmtilesTileId({1, 1, 1}), 3u);
    EXPECT_EQ(pmtilesTileId({1, 1, 0}), 4u);
    EXPECT_EQ(pmtilesTileId({2, 0, 0}), 5u);
    // The reference implementation's test values (zxyToTileId).
    EXPECT_EQ(pmtilesTileId({12, 3423, 1763}), 19078479u);
    // Inverse over whole zooms, ids contiguous per zoom.
    for (int z = 0; z <= 6; ++z) {
        std::vector<bool> seen(size_t(1) << (2 * z));
        const uint64_t first = ((uint64_t(1) << (2 * z)) - 1) / 3;
        for (int64_t y = 0; y < (int64_t(1) << z); ++y)
            for (int64_t x = 0; x < (int64_t(1) << z); ++x) {
                const uint64_t id = pmtilesTileId({z, x, y});
                ASSERT_GE(id, first);
                ASSERT_LT(id - first, seen.size());
                EXPECT_FALSE(seen[id - first]);
                seen[id - first] = true;
                EXPECT_EQ(pmtilesTileKey(id), (TileKey{z, x, y}));
            }
    }
    EXPECT_EQ(pmtilesTileKey(pmtilesTileId({26, 67108863, 0})), (TileKey{26, 67108863, 0}));
    EXPECT_THROW(pmtilesTileId({27, 0, 0}), Error);
    EXPECT_THROW(pmtilesTileId({2, 4, 0}), Error);
    EXPECT_THROW(pmtilesTileId({2, 0, -1}), Error);
}

TEST(Pmtiles, WritesAndReadsBackWithRunsAndDuplicates)
{
    const test::ScratchDir dir;
    // Zoom 2 in id order: a run of identical tiles, one unique, a repeat of the first content.
    std::vector<std::pair<TileKey, std::string>> tiles;
    for (uint64_t id = 5; id < 21; ++id)
        tiles.push_back({pmtilesTileKey(id), id < 9     ? "sea"
                                             : id == 9  ? "peak"
                                             : id == 20 ? "sea"
                                                        : "land " + std::to_string(id)});
    PmtilesHeader header;
    header.tile_type = PmtilesType::Png;
    header.min_zoom = 2;
    header.max_zoom = 2;
    header.bounds = {86.75, 27.83, 87.0, 28.0};
    const std::string path = writeArchive(dir, "t.pmtiles", tiles, header);
    const PmtilesReader r(path);
    EXPECT_EQ(r.addressedTiles(), 16u);
    EXPECT_EQ(r.tileEntries(), 13u) << "ids 5-8 are one run";
    EXPECT_EQ(r.tileContents(), 12u) << "'sea' is stored once";
    EXPECT_TRUE(r.clustered());
    EXPECT_EQ(r.header().tile_type, PmtilesType::Png);
    EXPECT_NEAR(r.header().bounds.west, 86.75, 1e-7);
    EXPECT_EQ(nlohmann::json::parse(r.metadata())["name"], "test");
    for (const auto& [k, bytes] : tiles)
        EXPECT_EQ(r.tile(k), bytesOf(bytes)) << k.z << "/" << k.x << "/" << k.y;
    EXPECT_FALSE(r.tile({1, 0, 0}));
    EXPECT_FALSE(r.tile({3, 0, 0}));
}

TEST(Pmtiles, LeafDirectoriesWhenTheRootDoesNotFit)
{
    const test::ScratchDir dir;
    // 50,000 distinct tiles of zoom 8 and 9: far past what a 16 KiB root holds.
    std::vector<std::pair<TileKey, std::string>> tiles;
    for (uint64_t id = pmtilesTileId({8, 0, 0}); tiles.size() < 50000; ++id)
        tiles.push_back({pmtilesTileKey(id), "tile " + std::to_string(id * 7919 % 1000003)});
    const std::string path = writeArchive(dir, "big.pmtiles", tiles);
    const PmtilesReader r(path);
    EXPECT_EQ(r.addressedTiles(), 50000u);
    for (size_t i = 0; i < tiles.size(); i += 997)
        EXPECT_EQ(r.tile(tiles[i].first), bytesOf(tiles[i].second));
    EXPECT_EQ(r.tile(tiles.back().first), bytesOf(tiles.back().second));
}

TEST(Pmtiles, RefusesOutOfOrderTilesAndHostileFiles)
{
    const test::ScratchDir dir;
    {
        AtomicOutput out(dir.path("x.pmtiles"));
        PmtilesWriter w(out.fd(), "x.pmtiles");
        w.add(7, bytesOf("a"));
        EXPECT_THROW(w.add(7, bytesOf("b")), Error);
        EXPECT_THROW(w.add(3, bytesOf("b")), Error);
        EXPECT_THROW(w.add(8, {}), Error);
    }
    const std::string path =
        writeArchive(dir, "ok.pmtiles", {{{1, 0, 0}, "one"}, {{1, 0, 1}, "two"}});
    const std::string good = test::readFile(path);
    const auto refused = [&](const std::string& bytes, const char* what) {
        const std::string bad = dir.path("bad.pmtiles");
        std::ofstream(bad, std::ios::binary) << bytes;
        try {
            const PmtilesReader r(bad);
            (void)r.tile({1, 0, 0});
            ADD_FAILURE() << what << ": accepted";
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find("bad.pmtiles"), std::string::npos) << e.what();
        }
    };
    // Every truncation of the header and root directory region.
    for (size_t n = 0; n < 127 + 40; n += 3)
        refused(good.substr(0, n), "truncated");
    std::string b = good;
    b[0] = 'X';
    refused(b, "magic");
    b = good;
    b[7] = 2;
    refused(b, "version");
    b = good;
    b[97] = 9;
    refused(b, "internal compression");
    b = good;
    b[100] = 5; // min zoom above max zoom
    refused(b, "zooms");
    b = good;
    b[8 + 8] = char(0xff); // root length past the file
    refused(b, "root length");
    b = good;
    b[8 + 7 * 8 + 6] = 1; // tile data length past the file
    refused(b, "tile data");
    b = good;
    b[127 + 12] ^= 0x5a; // the compressed root directory
    refused(b, "root bytes");
}
