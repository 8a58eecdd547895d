#pragma once
// Terrain-RGB tiles: heights at a Web Mercator tile's pixel centres packed into 24-bit RGB,
// as MapLibre GL's raster-dem sources read them, in either encoding:
//   Mapbox:    h = −10000 + (R·65536 + G·256 + B) · 0.1      (native step 0.1 m)
//   Terrarium: h = R·256 + G + B/256 − 32768                  (native step 1/256 m)
//
// Vertical step. A producer may round heights coarser than the encoding's step (smaller
// files: the low bits turn to runs of zeros), and where the step exceeds what the ground
// changes across a pixel, flat land shows terraces in the client's hillshade (what mapterhorn's
// users report of Terrarium tiles). ridge's rule: the step is the encoding's native step
// times the largest power of two that keeps it within
//     s ≤ pixel size / 1000   and   s ≤ max(the archive's Err(P) over the tile, native step)
// so that ground sloping 0.1 % or more (1 m a kilometre: river plains, coasts) changes by at
// least a step from pixel to pixel — no plateau two pixels wide, no terrace — and rounding
// never adds more than half the archive's own bound. Every pixel then decodes within s/2 of
// the archive level's surface at its centre, and within s/2 + Err(P) of the finest samples
// under it (bilinear between them).
#include "ridge/web/image_codec.h"
#include "ridge/web/tile_grid.h"

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace ridge::web {

class TileSampler;

enum class RgbEncoding { Mapbox, Terrarium };
const char* rgbEncodingName(RgbEncoding encoding); // "mapbox", "terrarium"
std::optional<RgbEncoding> parseRgbEncoding(std::string_view name);

// The encoding's own step, metres.
double nativeStep(RgbEncoding encoding);
// The rule above: native · 2^k for the largest k ≥ 0 within both limits.
double rgbStep(RgbEncoding encoding, double pixel_metres, double archive_error);
// `height` rounded to `step` (a native · 2^k) and clamped into the encoding's range.
std::array<uint8_t, 3> encodeRgbHeight(RgbEncoding encoding, double height, double step);
double decodeRgbHeight(RgbEncoding encoding, const uint8_t* rgb);

struct RgbTile {
    std::vector<uint8_t> image; // PNG or WebP, lossless
    double step = 0.0;          // metres (the rule above)
    double archive_error = 0.0; // the largest Err(P) of the patches read
    int level = 0;              // the archive level read
    size_t missing = 0;         // pixels off the archive or on its nodata (tile_sampler.h)
};

// The tile of Web Mercator key `k`, `size` pixels a side, or nullopt when it misses the
// archive. Throws ridge::Error as TileSampler::sampleMercator does.
std::optional<RgbTile> makeRgbTile(TileSampler& sampler, TileKey k, int size, RgbEncoding encoding,
                                   ImageFormat format);

} // namespace ridge::web
