#pragma once
// Lossless RGB images in memory for terrain-RGB tiles: PNG through libpng's simplified API
// and WebP lossless through libwebp (both Debian packages). The decoders are what tests and
// `ridge tiles --verify`-style checks read tiles back with.
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace ridge::web {

enum class ImageFormat { Png, Webp };
const char* imageFormatName(ImageFormat format);  // "png", "webp"
const char* imageContentType(ImageFormat format); // "image/png", "image/webp"

// `rgb`: width × height × 3 bytes, rows from the top. Throws ridge::Error when the encoder
// fails or the size is not in [1, 16384].
std::vector<uint8_t> encodeRgbImage(ImageFormat format, std::span<const uint8_t> rgb, int width,
                                    int height);

struct RgbImage {
    int width = 0, height = 0;
    std::vector<uint8_t> rgb; // width × height × 3
};
// Throws ridge::Error for bytes that are not a whole image of that format (or larger than
// 16384 pixels a side).
RgbImage decodeRgbImage(ImageFormat format, std::span<const uint8_t> bytes);

} // namespace ridge::web
