#pragma once
// One grey image <-> one JPEG 2000 codestream, through either Debian library: OpenJPEG
// (JPEG 2000 Part 1, EBCOT) or OpenJPH (Part 15, HTJ2K: the same wavelets with a faster
// block coder). The jpeg2000 height codec and the codec-bench anchor use these and nothing
// else of the libraries, so their quirks (callbacks, streams, exceptions) stay in two files.
//
// Codestreams only (.j2k / .j2c, no JP2 boxes): 64x64 code-blocks, one quality layer, up to
// 6 decompositions (fewer for small images). Decoding takes untrusted bytes: the image must
// be exactly one unsigned component of the expected size and precision, else it is refused.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace ridge::j2k {

enum class Library : uint8_t { OpenJpeg = 0, Htj2k = 1 };

const char* libraryName(Library library);
std::string libraryVersion(Library library);

// How hard one encode compresses.
//   reversible: the 5/3 integer wavelet, lossless (`value` ignored).
//   else the 9/7 wavelet and `value`: for OpenJPEG the target compression ratio against the
//   raw image at its precision (>= 1; its PCRD rate control), for OpenJPH the quantization
//   step of the lowest band relative to the sample range (> 0; HTJ2K has no rate control).
struct Rate {
    bool reversible = true;
    double value = 0;
};

// Encodes width x height samples (row-major, each in [0, 2^bits - 1], 1 <= bits <= 16).
// Returns false and sets *error when the library fails.
bool encode(Library library, const int32_t* samples, int width, int height, int bits, Rate rate,
            std::vector<uint8_t>* out, std::string* error);

// Decodes a codestream that must hold exactly one unsigned width x height component of `bits`
// precision into `samples`, clamped to [0, 2^bits - 1] (a lossy decode may overshoot).
// Returns false and sets *error for anything else, truncated or corrupt bytes included.
// HTJ2K: OpenJPH 0.9 asserts (aborts) on some malformed codestreams, so untrusted HTJ2K is
// decoded only when RIDGE_ALLOW_HTJ2K=1; `trusted` is for a codestream just encoded here.
bool decode(Library library, const uint8_t* bytes, size_t size, int width, int height, int bits,
            int32_t* samples, std::string* error, bool trusted = false);
bool htj2kDecodingAllowed();

// The length of the codestream at the start of `bytes`, by its markers: SOC, the main header's
// marker segments, each tile-part by its SOT's Psot (which must be non-zero), then EOC; the
// result includes the EOC. 0, with *error set, when the markers do not hold together. A result
// below `size` means bytes after the EOC marker, which neither library reports.
size_t codestreamSize(const uint8_t* bytes, size_t size, std::string* error);

// Decompositions used for a width x height image: each halves the smaller side, and the
// lowest resolution keeps at least one sample (at most 6, OpenJPEG's default).
int decompositionsFor(int width, int height);

} // namespace ridge::j2k
