// quantized-mesh-1.0: golden bytes, round trips, every malformed field refused, the vertex
// order the index coding needs, and the header's bounding volumes.
#include "ridge/web/quantized_mesh.h"

#include "ridge/core/error.h"
#include "ridge/lod/ellipsoid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>
#include <random>
#include <set>

using namespace ridge;
using namespace ridge::web;

namespace {

// Two triangles over the whole tile, every extension present.
QuantizedMesh square()
{
    QuantizedMesh m;
    m.center = {1.0, 2.0, 3.0};
    m.min_height = -10.f;
    m.max_height = 90.f;
    m.bounding_sphere = {1.0, 2.0, 3.0, 4.0};
    m.horizon_occlusion = {0.5, 0.25, 0.125};
    m.u = {0, 32767, 32767, 0};
    m.v = {0, 0, 32767, 32767};
    m.height = {0, 100, 32767, 5};
    m.triangles = {0, 1, 2, 0, 2, 3};
    m.west = {0, 3};
    m.south = {0, 1};
    m.east = {1, 2};
    m.north = {3, 2};
    m.oct_normals = {1, 2, 3, 4, 5, 6, 7, 8};
    m.water_mask = {255};
    m.metadata = "{}";
    return m;
}

std::string hex(const std::vector<uint8_t>& b)
{
    std::string s;
    char buf[3];
    for (uint8_t c : b) {
        std::snprintf(buf, sizeof buf, "%02x", c);
        s += buf;
    }
    return s;
}

void expectSameMesh(const QuantizedMesh& a, const QuantizedMesh& b)
{
    EXPECT_EQ(a.center, b.center);
    EXPECT_EQ(a.min_height, b.min_height);
    EXPECT_EQ(a.max_height, b.max_height);
    EXPECT_EQ(a.bounding_sphere, b.bounding_sphere);
    EXPECT_EQ(a.horizon_occlusion, b.horizon_occlusion);
    EXPECT_EQ(a.u, b.u);
    EXPECT_EQ(a.v, b.v);
    EXPECT_EQ(a.height, b.height);
    EXPECT_EQ(a.triangles, b.triangles);
    EXPECT_EQ(a.west, b.west);
    EXPECT_EQ(a.south, b.south);
    EXPECT_EQ(a.east, b.east);
    EXPECT_EQ(a.north, b.north);
    EXPECT_EQ(a.oct_normals, b.oct_normals);
    EXPECT_EQ(a.water_mask, b.water_mask);
    EXPECT_EQ(a.metadata, b.metadata);
}

} // namespace

TEST(QuantizedMesh, EncodesTheGoldenBytes)
{
    const std::vector<uint8_t> bytes = encodeQuantizedMesh(square());
    // After the 88-byte header, little-endian: 4 vertices; each array zig-zag delta coded
    // (u: 0, +32767, 0, −32767 → 0, 0xfffe, 0, 0xfffd; heights 0, +100, +32667, −32762);
    // no padding (116 bytes so far); 2 triangles, codes 0 0 0 3 1 0 (high-water mark); the
    // four edges; extensions 1 (8 bytes), 2 (1 byte), 4 (its length, then "{}").
    const std::string expected_tail = "04000000"
                                      "0000feff0000fdff"
                                      "00000000feff0000"
                                      "0000c80036fff3ff"
                                      "02000000"
                                      "000000000000030001000000"
                                      "0200000000000300"
                                      "0200000000000100"
                                      "0200000001000200"
                                      "0200000003000200"
                                      "01080000000102030405060708"
                                      "0201000000ff"
                                      "0406000000020000007b7d";
    ASSERT_GT(bytes.size(), 88u);
    EXPECT_EQ(hex(std::vector<uint8_t>(bytes.begin() + 88, bytes.end())), expected_tail);
    // The header: the centre's doubles, then the two float heights, the sphere, the point.
    double cx, radius, hz;
    float hmin, hmax;
    std::memcpy(&cx, bytes.data(), 8);
    std::memcpy(&hmin, bytes.data() + 24, 4);
    std::memcpy(&hmax, bytes.data() + 28, 4);
    std::memcpy(&radius, bytes.data() + 56, 8);
    std::memcpy(&hz, bytes.data() + 80, 8);
    EXPECT_EQ(cx, 1.0);
    EXPECT_EQ(hmin, -10.f);
    EXPECT_EQ(hmax, 90.f);
    EXPECT_EQ(radius, 4.0);
    EXPECT_EQ(hz, 0.125);
}

TEST(QuantizedMesh, RoundTripsEveryField)
{
    const QuantizedMesh m = square();
    expectSameMesh(decodeQuantizedMesh(encodeQuantizedMesh(m)), m);
    QuantizedMesh bare = m;
    bare.oct_normals.clear();
    bare.water_mask.clear();
    bare.metadata.clear();
    expectSameMesh(decodeQuantizedMesh(encodeQuantizedMesh(bare)), bare);
}

TEST(QuantizedMesh, ManyVerticesUse32BitIndicesAlignedToFourBytes)
{
    // 65,537 vertices in a fan strip: one more than 16-bit indices hold. An odd count puts the
    // index block 2 bytes off 4-byte alignment, so the padding is exercised.
    QuantizedMesh m;
    const uint32_t n = 65537;
    for (uint32_t i = 0; i < n; ++i) {
        m.u.push_back(uint16_t(i % 32768));
        m.v.push_back(uint16_t(i / 32768 * 1000));
        m.height.push_back(uint16_t(i % 97));
    }
    for (uint32_t i = 2; i < n; ++i)
        m.triangles.insert(m.triangles.end(), {i - 2, i - 1, i});
    m.west = {0, n - 1};
    const std::vector<uint8_t> bytes = encodeQuantizedMesh(m);
    EXPECT_EQ((88 + 4 + 6 * size_t(n) + 2) % 4, 0u) << "padding before the indices";
    expectSameMesh(decodeQuantizedMesh(bytes), m);
}

TEST(QuantizedMesh, EncodeRefusesWhatTheFormatCannotSay)
{
    const auto refused = [](auto edit) {
        QuantizedMesh m = square();
        edit(m);
        EXPECT_THROW(encodeQuantizedMesh(m), Error);
    };
    refused([](QuantizedMesh& m) { m.u[1] = 32768; });
    refused([](QuantizedMesh& m) { m.v.pop_back(); });
    refused([](QuantizedMesh& m) { m.triangles[5] = 4; });
    refused([](QuantizedMesh& m) { m.triangles = {0, 2, 1}; }); // 2 before 1: not first-use order
    refused([](QuantizedMesh& m) { m.triangles.pop_back(); });
    refused([](QuantizedMesh& m) { m.north[0] = 9; });
    refused([](QuantizedMesh& m) { m.center[1] = NAN; });
    refused([](QuantizedMesh& m) { m.max_height = INFINITY; });
    refused([](QuantizedMesh& m) { m.min_height = 100.f; });
    refused([](QuantizedMesh& m) { m.oct_normals.pop_back(); });
    refused([](QuantizedMesh& m) { m.water_mask = {0, 255}; });
}

TEST(QuantizedMesh, DecodeRefusesEveryMalformedField)
{
    const std::vector<uint8_t> good = encodeQuantizedMesh(square());
    // Truncated anywhere: refused, whatever field the cut falls in (extensions included).
    const size_t vertices = 88, indices = 88 + 4 + 24 + 4, edges = indices + 12;
    const size_t extensions = edges + 4 * 8, water = extensions + 13, metadata = water + 6;
    ASSERT_EQ(good.size(), metadata + 11);
    for (size_t n = 0; n < good.size(); ++n) {
        if (n == extensions || n == water || n == metadata) // a whole tile, fewer extensions
            continue;
        EXPECT_THROW(decodeQuantizedMesh(std::span(good.data(), n)), Error) << n << " bytes";
    }
    const auto refused = [&](size_t at, std::vector<uint8_t> with) {
        std::vector<uint8_t> b = good;
        std::copy(with.begin(), with.end(), b.begin() + std::ptrdiff_t(at));
        EXPECT_THROW(decodeQuantizedMesh(b), Error) << "bytes at " << at;
    };
    refused(vertices, {0xff, 0xff, 0xff, 0x7f});    // a vertex count past the bytes
    refused(vertices + 4 + 2, {0x00, 0x00});        // u 0, 0, 0, then −32767: below 0
    refused(vertices + 4 + 6, {0xfc, 0xff});        // u 32767, then +32766: past 32767
    refused(indices - 4, {0x00, 0x00, 0x01, 0x00}); // 65,536 triangles: past the bytes
    refused(indices + 6, {0x05, 0x00});             // a code past the highest vertex so far
    refused(edges, {0x00, 0x00, 0x01, 0x00});       // 65,536 west vertices: past the bytes
    refused(edges + 4, {0x07, 0x00});               // a west index out of range
    refused(extensions + 1, {0x07});                // normals of 7 bytes for 4 vertices
    refused(water + 1, {0x02});                     // a water mask of 2 bytes
    refused(metadata + 5, {0x03}); // a JSON length that does not fill its extension
    std::vector<uint8_t> trailing = good;
    trailing.push_back(9);
    EXPECT_THROW(decodeQuantizedMesh(trailing), Error) << "a byte past the last extension";
    // An unknown extension is skipped, as clients do.
    std::vector<uint8_t> unknown = good;
    unknown.insert(unknown.end(), {0x07, 0x02, 0x00, 0x00, 0x00, 0xaa, 0xbb});
    EXPECT_NO_THROW(decodeQuantizedMesh(unknown));
}

TEST(QuantizedMesh, OrderForIndexCodingKeepsTheSurface)
{
    // A 5 × 5 grid of vertices listed in a scrambled order; after ordering it encodes, and
    // every triangle is the same triangle of (u, v, h) as before.
    QuantizedMesh m;
    std::mt19937 rng(7);
    std::vector<uint32_t> slot(25);
    for (uint32_t i = 0; i < 25; ++i)
        slot[i] = i;
    std::shuffle(slot.begin(), slot.end(), rng);
    m.u.resize(25);
    m.v.resize(25);
    m.height.resize(25);
    for (uint32_t r = 0; r < 5; ++r)
        for (uint32_t c = 0; c < 5; ++c) {
            const uint32_t s = slot[r * 5 + c];
            m.u[s] = uint16_t(c * 8191);
            m.v[s] = uint16_t(r * 8191);
            m.height[s] = uint16_t((c * 37 + r * 11) % 200);
        }
    auto at = [&](uint32_t c, uint32_t r) { return slot[r * 5 + c]; };
    for (uint32_t r = 0; r < 4; ++r)
        for (uint32_t c = 0; c < 4; ++c)
            m.triangles.insert(m.triangles.end(), {at(c, r), at(c + 1, r), at(c + 1, r + 1),
                                                   at(c, r), at(c + 1, r + 1), at(c, r + 1)});
    for (uint32_t r = 0; r < 5; ++r)
        m.west.push_back(at(0, r));
    m.oct_normals.resize(50);
    for (uint32_t i = 0; i < 25; ++i) {
        m.oct_normals[2 * i] = uint8_t(m.u[i] / 8191);
        m.oct_normals[2 * i + 1] = uint8_t(m.v[i] / 8191);
    }
    const QuantizedMesh before = m;
    EXPECT_THROW(encodeQuantizedMesh(m), Error) << "scrambled: not first-use order";
    orderForIndexCoding(m);
    const QuantizedMesh after = decodeQuantizedMesh(encodeQuantizedMesh(m));
    using Corner = std::array<uint16_t, 3>;
    auto triangleSet = [](const QuantizedMesh& q) {
        std::multiset<std::array<Corner, 3>> out;
        for (size_t t = 0; t < q.triangles.size(); t += 3) {
            std::array<Corner, 3> tri;
            for (int k = 0; k < 3; ++k) {
                const uint32_t i = q.triangles[t + size_t(k)];
                tri[size_t(k)] = {q.u[i], q.v[i], q.height[i]};
            }
            // Rotated to start at the least corner: the same triangle, same winding.
            std::rotate(tri.begin(), std::min_element(tri.begin(), tri.end()), tri.end());
            out.insert(tri);
        }
        return out;
    };
    EXPECT_EQ(triangleSet(after), triangleSet(before));
    for (size_t k = 0; k < 5; ++k)
        EXPECT_EQ(after.u[after.west[k]], 0) << "the west edge follows its vertices";
    for (uint32_t i = 0; i < 25; ++i) {
        EXPECT_EQ(after.oct_normals[2 * i], after.u[i] / 8191) << "normals follow their vertex";
        EXPECT_EQ(after.oct_normals[2 * i + 1], after.v[i] / 8191);
    }
}

TEST(QuantizedMesh, BoundingVolumesHoldEveryVertexAndTheHorizonPointIsCesiums)
{
    // A tile over the Himalaya (84–88° E, 26–30° N) with heights up to 8,848 m.
    const lod::Ellipsoid e = lod::Ellipsoid::wgs84();
    std::vector<std::array<double, 3>> ecef;
    std::vector<double> heights;
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> lon(84, 88), lat(26, 30), h(-50, 8848);
    for (int i = 0; i < 500; ++i) {
        const double z = h(rng);
        const glm::dvec3 p = lod::geodeticToEcef(e, lon(rng) * std::numbers::pi / 180,
                                                 lat(rng) * std::numbers::pi / 180, z);
        ecef.push_back({p.x, p.y, p.z});
        heights.push_back(z);
    }
    QuantizedMesh m;
    EXPECT_TRUE(setBoundingVolumes(m, ecef, heights));
    for (const auto& p : ecef) {
        const double d = std::hypot(p[0] - m.bounding_sphere[0], p[1] - m.bounding_sphere[1],
                                    p[2] - m.bounding_sphere[2]);
        EXPECT_LE(d, m.bounding_sphere[3] * (1 + 1e-12));
    }
    EXPECT_LE(double(m.min_height), *std::min_element(heights.begin(), heights.end()));
    EXPECT_GE(double(m.max_height), *std::max_element(heights.begin(), heights.end()));
    // Cesium's horizon test (EllipsoidalOccluder.isScaledSpacePointVisible): from any camera
    // that sees a vertex over the ellipsoid's horizon, the point must be visible too, or the
    // client would cull a tile that shows.
    const double scale[3] = {1 / e.a, 1 / e.a, 1 / e.b()};
    auto visible = [&](const double c[3], const double p[3]) {
        const double vh2 = c[0] * c[0] + c[1] * c[1] + c[2] * c[2] - 1.0;
        const double vt[3] = {p[0] - c[0], p[1] - c[1], p[2] - c[2]};
        const double vt_dot_vc = -(vt[0] * c[0] + vt[1] * c[1] + vt[2] * c[2]);
        const double vt2 = vt[0] * vt[0] + vt[1] * vt[1] + vt[2] * vt[2];
        return !(vt_dot_vc > vh2 && vt_dot_vc * vt_dot_vc / vt2 > vh2);
    };
    std::uniform_real_distribution<double> clon(40, 130), clat(-10, 70), calt(1e3, 2e7);
    int cameras_seeing_some_vertex = 0;
    for (int k = 0; k < 2000; ++k) {
        const glm::dvec3 cp = lod::geodeticToEcef(e, clon(rng) * std::numbers::pi / 180,
                                                  clat(rng) * std::numbers::pi / 180, calt(rng));
        const double c[3] = {cp.x * scale[0], cp.y * scale[1], cp.z * scale[2]};
        bool any = false;
        for (const auto& p : ecef) {
            const double s[3] = {p[0] * scale[0], p[1] * scale[1], p[2] * scale[2]};
            any = any || visible(c, s);
        }
        cameras_seeing_some_vertex += any;
        if (any) {
            EXPECT_TRUE(visible(c, m.horizon_occlusion.data())) << "camera " << k;
        }
    }
    EXPECT_GT(cameras_seeing_some_vertex, 500);
    EXPECT_LT(cameras_seeing_some_vertex, 2000) << "some cameras must be behind the horizon";
}
