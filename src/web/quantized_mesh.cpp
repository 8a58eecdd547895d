#include "ridge/web/quantized_mesh.h"

#include "ridge/core/error.h"
#include "ridge/lod/ellipsoid.h"

#include <meshoptimizer.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <type_traits>

namespace ridge::web {

namespace {

constexpr size_t kHeaderBytes = 88;
constexpr uint8_t kOctNormalsId = 1, kWaterMaskId = 2, kMetadataId = 4;
constexpr size_t kWaterMaskSide = 256;
// Where the horizon occlusion point goes when no point is exact (ellipsoid radii, scaled
// frame): far out, the tile is hidden only from cameras in the half-space opposite its centre.
constexpr double kFarHorizonPoint = 1e3;

[[noreturn]] void fail(const std::string& what)
{
    throw Error("quantized-mesh: " + what);
}

// Little-endian writer.
class Writer {
  public:
    template <class T> void put(T value)
    {
        static_assert(std::is_arithmetic_v<T>);
        uint8_t b[sizeof(T)];
        std::memcpy(b, &value, sizeof(T));
        if constexpr (std::endian::native == std::endian::big)
            std::reverse(b, b + sizeof(T));
        out.insert(out.end(), b, b + sizeof(T));
    }
    void pad(size_t alignment)
    {
        while (out.size() % alignment)
            out.push_back(0);
    }
    std::vector<uint8_t> out;
};

// Little-endian reader; every read checks what is left and names the field.
class Reader {
  public:
    explicit Reader(std::span<const uint8_t> b) : bytes_(b) {}
    template <class T> T get(const char* field)
    {
        need(sizeof(T), field);
        uint8_t b[sizeof(T)];
        std::memcpy(b, bytes_.data() + at_, sizeof(T));
        if constexpr (std::endian::native == std::endian::big)
            std::reverse(b, b + sizeof(T));
        at_ += sizeof(T);
        T v;
        std::memcpy(&v, b, sizeof(T));
        return v;
    }
    void need(size_t n, const char* field) const
    {
        if (n > bytes_.size() - at_)
            fail(std::string("truncated at ") + field + " (byte " + std::to_string(at_) + " of " +
                 std::to_string(bytes_.size()) + ")");
    }
    void skip(size_t n, const char* field)
    {
        need(n, field);
        at_ += n;
    }
    void align(size_t alignment, const char* field)
    {
        skip((alignment - at_ % alignment) % alignment, field);
    }
    size_t left() const { return bytes_.size() - at_; }
    size_t at() const { return at_; }

  private:
    std::span<const uint8_t> bytes_;
    size_t at_ = 0;
};

uint16_t zigZag(int32_t d)
{
    return uint16_t(uint32_t((d << 1) ^ (d >> 31)));
}
int32_t unZigZag(uint16_t z)
{
    return int32_t(z >> 1) ^ -int32_t(z & 1);
}

void checkFinite(double v, const char* field)
{
    if (!std::isfinite(v))
        fail(std::string(field) + " is not finite");
}

void checkMesh(const QuantizedMesh& m)
{
    for (double c : m.center)
        checkFinite(c, "the centre");
    for (double c : m.bounding_sphere)
        checkFinite(c, "the bounding sphere");
    for (double c : m.horizon_occlusion)
        checkFinite(c, "the horizon occlusion point");
    checkFinite(m.min_height, "the minimum height");
    checkFinite(m.max_height, "the maximum height");
    if (m.min_height > m.max_height)
        fail("minimum height above the maximum");
    const size_t n = m.vertexCount();
    if (m.v.size() != n || m.height.size() != n)
        fail("u, v and height arrays of different lengths");
    if (n > std::numeric_limits<uint32_t>::max() / 2)
        fail("too many vertices");
    for (const auto* a : {&m.u, &m.v, &m.height})
        for (uint16_t c : *a)
            if (c > QuantizedMesh::kMaxCoordinate)
                fail("a coordinate past 32767");
    if (m.triangles.size() % 3)
        fail("a triangle list that is not a multiple of 3");
    // High-water-mark coding: each index at most one past the highest seen so far.
    uint32_t next = 0;
    for (uint32_t i : m.triangles) {
        if (i >= n)
            fail("a triangle index out of range");
        if (i > next)
            fail("vertices not in order of first use (orderForIndexCoding)");
        next = std::max(next, i + 1);
    }
    for (const auto* e : {&m.west, &m.south, &m.east, &m.north})
        for (uint32_t i : *e)
            if (i >= n)
                fail("an edge index out of range");
    if (!m.oct_normals.empty() && m.oct_normals.size() != 2 * n)
        fail("oct-encoded normals not 2 bytes a vertex");
    if (!m.water_mask.empty() && m.water_mask.size() != 1 &&
        m.water_mask.size() != kWaterMaskSide * kWaterMaskSide)
        fail("a water mask of neither 1 nor 65536 bytes");
}

void putIndices(Writer& w, const std::vector<uint32_t>& indices, bool wide)
{
    for (uint32_t i : indices)
        wide ? w.put<uint32_t>(i) : w.put<uint16_t>(uint16_t(i));
}

std::vector<uint32_t> getIndices(Reader& r, size_t count, bool wide, size_t vertices,
                                 const char* field)
{
    r.need(count * (wide ? 4 : 2), field);
    std::vector<uint32_t> out(count);
    for (uint32_t& i : out) {
        i = wide ? r.get<uint32_t>(field) : r.get<uint16_t>(field);
        if (i >= vertices)
            fail(std::string(field) + ": index " + std::to_string(i) + " of " +
                 std::to_string(vertices) + " vertices");
    }
    return out;
}

void putExtension(Writer& w, uint8_t id, std::span<const uint8_t> payload)
{
    w.put<uint8_t>(id);
    w.put<uint32_t>(uint32_t(payload.size()));
    w.out.insert(w.out.end(), payload.begin(), payload.end());
}

} // namespace

std::vector<uint8_t> encodeQuantizedMesh(const QuantizedMesh& m)
{
    checkMesh(m);
    Writer w;
    for (double c : m.center)
        w.put(c);
    w.put(m.min_height);
    w.put(m.max_height);
    for (double c : m.bounding_sphere)
        w.put(c);
    for (double c : m.horizon_occlusion)
        w.put(c);

    const size_t n = m.vertexCount();
    w.put<uint32_t>(uint32_t(n));
    for (const auto* a : {&m.u, &m.v, &m.height}) {
        int32_t previous = 0;
        for (uint16_t c : *a) {
            w.put<uint16_t>(zigZag(int32_t(c) - previous));
            previous = c;
        }
    }

    // Indices are 16-bit while every vertex fits; aligned to their size.
    const bool wide = n > 65536;
    w.pad(wide ? 4 : 2);
    w.put<uint32_t>(uint32_t(m.triangles.size() / 3));
    uint32_t highest = 0;
    for (uint32_t i : m.triangles) {
        const uint32_t code = highest - i;
        wide ? w.put<uint32_t>(code) : w.put<uint16_t>(uint16_t(code));
        if (code == 0)
            ++highest;
    }
    for (const auto* e : {&m.west, &m.south, &m.east, &m.north}) {
        w.put<uint32_t>(uint32_t(e->size()));
        putIndices(w, *e, wide);
    }

    if (!m.oct_normals.empty())
        putExtension(w, kOctNormalsId, m.oct_normals);
    if (!m.water_mask.empty())
        putExtension(w, kWaterMaskId, m.water_mask);
    if (!m.metadata.empty()) {
        Writer json;
        json.put<uint32_t>(uint32_t(m.metadata.size()));
        json.out.insert(json.out.end(), m.metadata.begin(), m.metadata.end());
        putExtension(w, kMetadataId, json.out);
    }
    return std::move(w.out);
}

QuantizedMesh decodeQuantizedMesh(std::span<const uint8_t> bytes)
{
    Reader r(bytes);
    QuantizedMesh m;
    r.need(kHeaderBytes, "the header");
    for (double& c : m.center)
        c = r.get<double>("the centre");
    m.min_height = r.get<float>("the minimum height");
    m.max_height = r.get<float>("the maximum height");
    for (double& c : m.bounding_sphere)
        c = r.get<double>("the bounding sphere");
    for (double& c : m.horizon_occlusion)
        c = r.get<double>("the horizon occlusion point");

    const uint32_t n = r.get<uint32_t>("the vertex count");
    r.need(size_t(n) * 6, "the vertex data");
    for (auto* a : {&m.u, &m.v, &m.height}) {
        a->resize(n);
        int32_t value = 0;
        for (uint16_t& c : *a) {
            value += unZigZag(r.get<uint16_t>("the vertex data"));
            if (value < 0 || value > QuantizedMesh::kMaxCoordinate)
                fail("a vertex coordinate out of [0, 32767] (" + std::to_string(value) + ")");
            c = uint16_t(value);
        }
    }

    const bool wide = n > 65536;
    r.align(wide ? 4 : 2, "the index padding");
    const uint32_t triangles = r.get<uint32_t>("the triangle count");
    r.need(size_t(triangles) * 3 * (wide ? 4 : 2), "the indices");
    m.triangles.resize(size_t(triangles) * 3);
    uint32_t highest = 0;
    for (uint32_t& i : m.triangles) {
        const uint32_t code =
            wide ? r.get<uint32_t>("the indices") : r.get<uint16_t>("the indices");
        if (code > highest)
            fail("an index code past the highest vertex so far");
        i = highest - code;
        if (code == 0 && ++highest > n)
            fail("the indices name more vertices than the tile has");
    }
    const char* edges[4] = {"the west edge", "the south edge", "the east edge", "the north edge"};
    std::vector<uint32_t>* lists[4] = {&m.west, &m.south, &m.east, &m.north};
    for (int e = 0; e < 4; ++e)
        *lists[e] = getIndices(r, r.get<uint32_t>(edges[e]), wide, n, edges[e]);

    while (r.left()) {
        const uint8_t id = r.get<uint8_t>("an extension id");
        const uint32_t length = r.get<uint32_t>("an extension length");
        r.need(length, "an extension");
        const std::span<const uint8_t> payload = bytes.subspan(r.at(), length);
        if (id == kOctNormalsId) {
            if (length != 2 * size_t(n))
                fail("oct-encoded normals not 2 bytes a vertex");
            m.oct_normals.assign(payload.begin(), payload.end());
        } else if (id == kWaterMaskId) {
            if (length != 1 && length != kWaterMaskSide * kWaterMaskSide)
                fail("a water mask of neither 1 nor 65536 bytes");
            m.water_mask.assign(payload.begin(), payload.end());
        } else if (id == kMetadataId) {
            Reader json(payload);
            const uint32_t json_length = json.get<uint32_t>("the metadata length");
            if (size_t(json_length) + 4 != length)
                fail("metadata length " + std::to_string(json_length) +
                     " does not fill its extension of " + std::to_string(length) + " bytes");
            m.metadata.assign(payload.begin() + 4, payload.end());
        }
        r.skip(length, "an extension");
    }
    checkMesh(m); // the header's numbers; what it checks besides, decoding ensured already
    return m;
}

double decodedHeight(const QuantizedMesh& m, uint32_t i)
{
    return double(m.min_height) + double(m.height[i]) / QuantizedMesh::kMaxCoordinate *
                                      double(m.max_height - m.min_height);
}

namespace {

// The barycentric weights of (u, v) in the triangle whose indices start at `first`, or false
// when it lies outside (beyond 1e-9 of them) or the triangle is degenerate.
bool triangleWeights(const QuantizedMesh& m, size_t first, double u, double v, double (&l)[3])
{
    constexpr double kInside = -1e-9; // barycentric slack: points on an edge belong to both
    const uint32_t a = m.triangles[first], b = m.triangles[first + 1], c = m.triangles[first + 2];
    const double ax = m.u[a], ay = m.v[a], bx = m.u[b], by = m.v[b], cx = m.u[c], cy = m.v[c];
    const double det = (bx - ax) * (cy - ay) - (cx - ax) * (by - ay);
    if (det == 0.0)
        return false;
    l[1] = ((u - ax) * (cy - ay) - (cx - ax) * (v - ay)) / det;
    l[2] = ((bx - ax) * (v - ay) - (u - ax) * (by - ay)) / det;
    l[0] = 1.0 - l[1] - l[2];
    return l[0] >= kInside && l[1] >= kInside && l[2] >= kInside;
}

} // namespace

double triangleHeightAt(const QuantizedMesh& m, size_t first, double u, double v)
{
    double l[3];
    if (!triangleWeights(m, first, u, v, l))
        return std::numeric_limits<double>::quiet_NaN();
    return l[0] * decodedHeight(m, m.triangles[first]) +
           l[1] * decodedHeight(m, m.triangles[first + 1]) +
           l[2] * decodedHeight(m, m.triangles[first + 2]);
}

double triangleValueAt(const QuantizedMesh& m, size_t first, double u, double v,
                       std::span<const double> values)
{
    double l[3];
    if (!triangleWeights(m, first, u, v, l))
        return std::numeric_limits<double>::quiet_NaN();
    return l[0] * values[m.triangles[first]] + l[1] * values[m.triangles[first + 1]] +
           l[2] * values[m.triangles[first + 2]];
}

double meshHeightAt(const QuantizedMesh& m, double u, double v)
{
    for (size_t t = 0; t + 2 < m.triangles.size(); t += 3)
        if (const double h = triangleHeightAt(m, t, u, v); !std::isnan(h))
            return h;
    return std::numeric_limits<double>::quiet_NaN();
}

void orderForIndexCoding(QuantizedMesh& m)
{
    const size_t n = m.vertexCount();
    if (m.triangles.empty() || n == 0)
        return;
    std::vector<uint32_t> indices(m.triangles.size());
    meshopt_optimizeVertexCache(indices.data(), m.triangles.data(), m.triangles.size(), n);
    std::vector<uint32_t> remap(n);
    // Vertices no triangle uses go last (~0 from meshoptimizer: kept, after the used ones).
    const size_t used =
        meshopt_optimizeVertexFetchRemap(remap.data(), indices.data(), indices.size(), n);
    uint32_t next_unused = uint32_t(used);
    for (uint32_t& r : remap)
        if (r == ~0u)
            r = next_unused++;
    for (uint32_t& i : indices)
        i = remap[i];
    m.triangles = std::move(indices);
    auto permute = [&](auto& values, size_t per_vertex) {
        auto out = values;
        for (size_t old = 0; old < n; ++old)
            for (size_t k = 0; k < per_vertex; ++k)
                out[remap[old] * per_vertex + k] = values[old * per_vertex + k];
        values = std::move(out);
    };
    permute(m.u, 1);
    permute(m.v, 1);
    permute(m.height, 1);
    if (!m.oct_normals.empty())
        permute(m.oct_normals, 2);
    for (auto* e : {&m.west, &m.south, &m.east, &m.north})
        for (uint32_t& i : *e)
            i = remap[i];
}

bool setBoundingVolumes(QuantizedMesh& m, std::span<const std::array<double, 3>> ecef,
                        std::span<const double> heights)
{
    if (ecef.empty() || ecef.size() != heights.size())
        fail("bounding volumes of " + std::to_string(ecef.size()) + " positions and " +
             std::to_string(heights.size()) + " heights");
    std::array<double, 3> lo = ecef[0], hi = ecef[0];
    for (const auto& p : ecef)
        for (int k = 0; k < 3; ++k) {
            checkFinite(p[size_t(k)], "a vertex position");
            lo[size_t(k)] = std::min(lo[size_t(k)], p[size_t(k)]);
            hi[size_t(k)] = std::max(hi[size_t(k)], p[size_t(k)]);
        }
    const auto [hmin, hmax] = std::minmax_element(heights.begin(), heights.end());
    m.min_height = float(*hmin);
    m.max_height = float(*hmax);
    if (double(m.min_height) > *hmin)
        m.min_height = std::nextafter(m.min_height, -INFINITY);
    if (double(m.max_height) < *hmax)
        m.max_height = std::nextafter(m.max_height, INFINITY);

    double radius = 0.0;
    for (int k = 0; k < 3; ++k)
        m.center[size_t(k)] = 0.5 * (lo[size_t(k)] + hi[size_t(k)]);
    for (const auto& p : ecef) {
        const double dx = p[0] - m.center[0], dy = p[1] - m.center[1], dz = p[2] - m.center[2];
        radius = std::max(radius, std::sqrt(dx * dx + dy * dy + dz * dz));
    }
    m.bounding_sphere = {m.center[0], m.center[1], m.center[2], radius};

    // Cesium's horizon culling point (EllipsoidalOccluder): in the ellipsoid-scaled frame,
    // along the direction of the centre, as far out as the vertex that needs it farthest.
    const lod::Ellipsoid e = lod::Ellipsoid::wgs84();
    const double scale[3] = {1.0 / e.a, 1.0 / e.a, 1.0 / e.b()};
    double dir[3] = {m.center[0] * scale[0], m.center[1] * scale[1], m.center[2] * scale[2]};
    const double dir_len = std::sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
    if (!(dir_len > 0.0)) {
        m.horizon_occlusion = {0.0, 0.0, kFarHorizonPoint};
        return false;
    }
    for (double& d : dir)
        d /= dir_len;
    double farthest = 0.0;
    bool exact = true;
    for (const auto& p : ecef) {
        const double s[3] = {p[0] * scale[0], p[1] * scale[1], p[2] * scale[2]};
        double mag2 = s[0] * s[0] + s[1] * s[1] + s[2] * s[2];
        double mag = std::sqrt(mag2);
        const double u[3] = {s[0] / mag, s[1] / mag, s[2] / mag};
        // Points below the ellipsoid count as on it.
        mag2 = std::max(1.0, mag2);
        mag = std::max(1.0, mag);
        const double cos_alpha = u[0] * dir[0] + u[1] * dir[1] + u[2] * dir[2];
        const double cx = u[1] * dir[2] - u[2] * dir[1], cy = u[2] * dir[0] - u[0] * dir[2],
                     cz = u[0] * dir[1] - u[1] * dir[0];
        const double sin_alpha = std::sqrt(cx * cx + cy * cy + cz * cz);
        const double cos_beta = 1.0 / mag;
        const double sin_beta = std::sqrt(mag2 - 1.0) * cos_beta;
        const double denominator = cos_alpha * cos_beta - sin_alpha * sin_beta;
        if (denominator > 0.0)
            farthest = std::max(farthest, 1.0 / denominator);
        else
            exact = false; // no finite point along `dir` sees this vertex's horizon
    }
    if (!exact)
        farthest = kFarHorizonPoint;
    m.horizon_occlusion = {dir[0] * farthest, dir[1] * farthest, dir[2] * farthest};
    return exact;
}

} // namespace ridge::web
