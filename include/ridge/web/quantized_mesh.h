#pragma once
// Cesium's quantized-mesh-1.0 terrain tiles: the byte format (encode, and a decoder that
// validates every field, for tests and for reading tiles back), the header's bounding
// volumes from geodetic vertices, and the vertex order the format's index coding needs.
//
// Layout (little-endian, github.com/CesiumGS/quantized-mesh): an 88-byte header (centre,
// min/max height, bounding sphere, horizon occlusion point), the vertex count and the u, v,
// height arrays (uint16 in [0, 32767], each zig-zag delta coded), the triangle count and
// indices (16-bit up to 65,536 vertices, else 32-bit, high-water-mark coded, after padding to
// their size), the west, south, east and north edge vertex lists (plain indices), then
// extensions (id, uint32 length, bytes): 1 oct-encoded vertex normals, 2 water mask, 4
// metadata (JSON).
//
// u runs east from the tile's west edge, v north from its south edge; triangles are
// counter-clockwise in (u, v), i.e. seen from above.
#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace ridge::web {

struct QuantizedMesh {
    static constexpr uint16_t kMaxCoordinate = 32767;

    // Header. ECEF metres except the horizon occlusion point, which is in the
    // ellipsoid-scaled frame (x/a, y/a, z/b).
    std::array<double, 3> center{};
    float min_height = 0.f, max_height = 0.f; // metres above the ellipsoid
    std::array<double, 4> bounding_sphere{};  // centre x, y, z, radius
    std::array<double, 3> horizon_occlusion{};

    // Per vertex, each in [0, kMaxCoordinate]; heights map [0, kMaxCoordinate] linearly onto
    // [min_height, max_height].
    std::vector<uint16_t> u, v, height;
    // Three vertex indices per triangle.
    std::vector<uint32_t> triangles;
    // The vertices on each edge of the tile (u = 0, v = 0, u = max, v = max).
    std::vector<uint32_t> west, south, east, north;

    // Extensions, each absent when empty: two oct-encoded bytes a vertex (1, "octvertexnormals");
    // one byte (all land 0 or all water 255) or 256 × 256 bytes, row 0 north (2, "watermask");
    // a JSON object (4, "metadata").
    std::vector<uint8_t> oct_normals;
    std::vector<uint8_t> water_mask;
    std::string metadata;

    size_t vertexCount() const { return u.size(); }
};

// Encodes `mesh`. Throws ridge::Error when a field breaks the format: arrays of unequal
// length, a coordinate past kMaxCoordinate, an index out of range, a triangle list whose
// first uses of vertices are not in vertex order (orderForIndexCoding makes them so), a
// non-finite header value, min_height > max_height, extensions of the wrong size.
std::vector<uint8_t> encodeQuantizedMesh(const QuantizedMesh& mesh);

// Decodes a tile (uncompressed). Throws ridge::Error naming the field for any byte the format
// does not allow: truncation at any field, out-of-range coordinates or indices, a high-water
// code past the next new vertex, an extension of the wrong length, trailing bytes, a
// non-finite header number or a minimum height above the maximum. Unknown
// extension ids are skipped, as clients do.
QuantizedMesh decodeQuantizedMesh(std::span<const uint8_t> bytes);

// The height, metres, vertex i decodes to (min + h/32767 · (max − min), in double).
double decodedHeight(const QuantizedMesh& mesh, uint32_t i);
// The height at (u, v) (the format's coordinates, fractional allowed) of the triangle whose
// indices start at triangles[first]: linear on it, NaN when the point lies outside it (by
// more than 1e-9 of its barycentric coordinates) or the triangle is degenerate.
double triangleHeightAt(const QuantizedMesh& mesh, size_t first, double u, double v);
// The same interpolation of per-vertex `values` (one per vertex) instead of the heights.
double triangleValueAt(const QuantizedMesh& mesh, size_t first, double u, double v,
                       std::span<const double> values);
// The mesh's height at (u, v): triangleHeightAt of the first triangle holding the point, NaN
// when none does. O(triangles) a call: for checking tiles, not for drawing them.
double meshHeightAt(const QuantizedMesh& mesh, double u, double v);

// Reorders triangles for the vertex cache and vertices by first use (meshoptimizer), as the
// high-water-mark index coding needs; edge lists and per-vertex extensions follow the
// vertices. The mesh's surface is unchanged.
void orderForIndexCoding(QuantizedMesh& mesh);

// Fills the header's centre, bounding sphere and horizon occlusion point (WGS 84) from the
// vertices' ECEF positions (and min/max height from `heights`). `ecef` and `heights` are
// per vertex; the centre is the bounding box's, the sphere holds every vertex, the
// horizon occlusion point is Cesium's (a point in the direction of the centre, in the scaled
// frame, whose horizon hides the tile exactly when it is hidden). Returns false when no point
// is exact: a vertex 90° or more from the centre's direction, as on zoom 0's hemisphere
// tiles; the point is then put 1,000 radii out along that direction, which a client culls only
// from the half-space behind the Earth's centre — parts of such a tile seen across that plane
// may be culled by a client that trusts the point.
bool setBoundingVolumes(QuantizedMesh& mesh, std::span<const std::array<double, 3>> ecef,
                        std::span<const double> heights);

} // namespace ridge::web
