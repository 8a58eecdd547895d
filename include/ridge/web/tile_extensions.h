#pragma once
// The quantized-mesh extensions a client may ask for, made from a tile's mesh and grid:
// "octvertexnormals" (1), "watermask" (2) and "metadata" (4, child availability).
//
// Normals: per vertex, the area-weighted mean of the normals of its triangles as the client
// places them (ECEF, WGS 84, from the quantized u, v, height), oct-encoded as Cesium's
// AttributeCompression.octEncode does (two bytes, 255 steps). Vertices on a tile's edge see
// only this tile's triangles, so lighting may show a faint seam there, as with every tiler
// that makes tiles one at a time.
//
// Water mask: Cesium's 256 × 256 bytes (0 land, 255 water; row 0 north, column 0 west),
// or one byte when the whole tile is one or the other. Each mask texel takes the flag of the
// grid sample nearest its centre.
#include "ridge/web/quantized_mesh.h"
#include "ridge/web/terrain_tile.h"

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace ridge::web {

// Bits of the extensions a request asks for (Cesium's Accept header, "extensions=a-b-c").
enum TileExtension : unsigned {
    kOctVertexNormals = 1u,
    kWaterMask = 2u,
    kMetadata = 4u,
};
// The extensions named in an Accept header value: every "extensions=" parameter's names,
// split on '-'; unknown names are ignored (a client may know more than the server).
unsigned parseAcceptedExtensions(std::string_view accept);
// "octvertexnormals-watermask-metadata" style, in id order; "" for none.
std::string extensionNames(unsigned extensions);

// Cesium's oct encoding of a unit vector (8 bits a component) and its decoding.
std::array<uint8_t, 2> octEncode(std::array<double, 3> n);
std::array<double, 3> octDecode(uint8_t x, uint8_t y);

// Two bytes a vertex (see above) for `mesh` as tile `key`'s.
std::vector<uint8_t> octVertexNormals(const QuantizedMesh& mesh, TileKey key);

// The mask from per-grid-sample water bits (`water[i]` non-zero: water), on `grid`'s lines.
// Throws ridge::Error when water's size is not the grid's.
std::vector<uint8_t> waterMask(const TileHeights& grid, std::span<const uint8_t> water);

// Child availability for the "metadata" extension: {"available":[[{"startX":..,"startY":..,
// "endX":..,"endY":..}]]} for the children range given (inclusive, TMS), or {} when none.
struct TileRange {
    int64_t x0 = 0, y0 = 0, x1 = -1, y1 = -1; // inclusive; empty when x1 < x0
    bool empty() const { return x1 < x0 || y1 < y0; }
    bool contains(int64_t x, int64_t y) const { return x >= x0 && x <= x1 && y >= y0 && y <= y1; }
};
std::string availabilityMetadata(std::span<const TileRange> children);

} // namespace ridge::web
