#include "ridge/web/terrain_rgb.h"

#include "ridge/web/tile_sampler.h"

#include <algorithm>
#include <cmath>

namespace ridge::web {

namespace {

constexpr double kMapboxOffset = 10000.0, kMapboxStep = 0.1;
constexpr double kTerrariumOffset = 32768.0, kTerrariumStep = 1.0 / 256.0;
constexpr double kMaxCode = double((1 << 24) - 1);
// Steps past native · 2^16 would round away all but the top byte; no tile needs that.
constexpr int kMaxStepShift = 16;

// The height as a 24-bit code in the encoding's native steps (unrounded).
double codeOf(RgbEncoding encoding, double height)
{
    return encoding == RgbEncoding::Mapbox ? (height + kMapboxOffset) / kMapboxStep
                                           : (height + kTerrariumOffset) / kTerrariumStep;
}

} // namespace

const char* rgbEncodingName(RgbEncoding encoding)
{
    return encoding == RgbEncoding::Mapbox ? "mapbox" : "terrarium";
}

std::optional<RgbEncoding> parseRgbEncoding(std::string_view name)
{
    if (name == "mapbox")
        return RgbEncoding::Mapbox;
    if (name == "terrarium")
        return RgbEncoding::Terrarium;
    return std::nullopt;
}

double nativeStep(RgbEncoding encoding)
{
    return encoding == RgbEncoding::Mapbox ? kMapboxStep : kTerrariumStep;
}

double rgbStep(RgbEncoding encoding, double pixel_metres, double archive_error)
{
    const double native = nativeStep(encoding);
    const double limit = std::min(pixel_metres / 1000.0, std::max(archive_error, native));
    double step = native;
    for (int k = 0; k < kMaxStepShift && step * 2.0 <= limit; ++k)
        step *= 2.0;
    return step;
}

std::array<uint8_t, 3> encodeRgbHeight(RgbEncoding encoding, double height, double step)
{
    const double unit = step / nativeStep(encoding); // a power of two
    double code = std::round(codeOf(encoding, height) / unit) * unit;
    code = std::clamp(code, 0.0, kMaxCode);
    const uint32_t c = uint32_t(code);
    return {uint8_t(c >> 16), uint8_t((c >> 8) & 0xff), uint8_t(c & 0xff)};
}

double decodeRgbHeight(RgbEncoding encoding, const uint8_t* rgb)
{
    if (encoding == RgbEncoding::Mapbox)
        return -kMapboxOffset + (rgb[0] * 65536.0 + rgb[1] * 256.0 + rgb[2]) * kMapboxStep;
    return rgb[0] * 256.0 + rgb[1] + rgb[2] / 256.0 - kTerrariumOffset;
}

std::optional<RgbTile> makeRgbTile(TileSampler& sampler, TileKey k, int size, RgbEncoding encoding,
                                   ImageFormat format)
{
    std::optional<MercatorSamples> samples = sampler.sampleMercator(k, size);
    if (!samples)
        return std::nullopt;
    RgbTile out;
    out.level = samples->level;
    out.archive_error = samples->archive_error;
    out.missing = samples->missing;
    // The pixel size where it is smallest in the tile (the pole-ward edge): the rule holds
    // for every pixel.
    const GeoRect r = WebMercatorXyz::rect(k);
    const double lat = std::max(std::abs(r.south), std::abs(r.north));
    out.step = rgbStep(encoding, WebMercatorXyz::metresPerPixel(k.z, lat, size), out.archive_error);
    std::vector<uint8_t> rgb(samples->heights.size() * 3);
    for (size_t i = 0; i < samples->heights.size(); ++i) {
        const std::array<uint8_t, 3> c = encodeRgbHeight(encoding, samples->heights[i], out.step);
        std::copy(c.begin(), c.end(), rgb.begin() + std::ptrdiff_t(3 * i));
    }
    out.image = encodeRgbImage(format, rgb, size, size);
    return out;
}

} // namespace ridge::web
