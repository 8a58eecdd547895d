#include "j2k_image.h"

#include <algorithm>
#include <cstdlib>

namespace ridge::j2k {

// Defined by the two library files.
bool encodeOpenJpeg(const int32_t* samples, int width, int height, int bits, Rate rate,
                    std::vector<uint8_t>* out, std::string* error);
bool decodeOpenJpeg(const uint8_t* bytes, size_t size, int width, int height, int bits,
                    int32_t* samples, std::string* error);
std::string openJpegVersion();
bool encodeHtj2k(const int32_t* samples, int width, int height, int bits, Rate rate,
                 std::vector<uint8_t>* out, std::string* error);
bool decodeHtj2k(const uint8_t* bytes, size_t size, int width, int height, int bits,
                 int32_t* samples, std::string* error);
std::string htj2kVersion();

const char* libraryName(Library library)
{
    return library == Library::Htj2k ? "HTJ2K (OpenJPH)" : "JPEG 2000 (OpenJPEG)";
}

std::string libraryVersion(Library library)
{
    return library == Library::Htj2k ? htj2kVersion() : openJpegVersion();
}

int decompositionsFor(int width, int height)
{
    const int smaller = std::min(width, height);
    int levels = 0;
    while (levels < 6 && (smaller >> (levels + 1)) > 0)
        ++levels;
    return levels;
}

bool encode(Library library, const int32_t* samples, int width, int height, int bits, Rate rate,
            std::vector<uint8_t>* out, std::string* error)
{
    if (width < 1 || height < 1 || bits < 1 || bits > 16 ||
        (!rate.reversible && !(rate.value > 0))) {
        *error = "invalid image or rate";
        return false;
    }
    return library == Library::Htj2k
               ? encodeHtj2k(samples, width, height, bits, rate, out, error)
               : encodeOpenJpeg(samples, width, height, bits, rate, out, error);
}

namespace {

uint32_t bigEndian(const uint8_t* p, int bytes)
{
    uint32_t v = 0;
    for (int k = 0; k < bytes; ++k)
        v = v << 8 | p[k];
    return v;
}

} // namespace

size_t codestreamSize(const uint8_t* b, size_t size, std::string* error)
{
    constexpr uint32_t kSoc = 0xFF4F, kSot = 0xFF90, kEoc = 0xFFD9;
    auto fail = [&](const char* what) {
        *error = what;
        return size_t{0};
    };
    if (size < 2 || bigEndian(b, 2) != kSoc)
        return fail("no SOC marker");
    // Main header: marker segments, each with its length (which counts its own two bytes).
    size_t at = 2;
    while (true) {
        if (size - at < 4)
            return fail("main header truncated");
        if (bigEndian(b + at, 2) == kSot)
            break;
        if (b[at] != 0xFF)
            return fail("main header: not a marker");
        const uint32_t length = bigEndian(b + at + 2, 2);
        if (length < 2 || length > size - at - 2)
            return fail("main header: marker segment runs past the codestream");
        at += 2 + length;
    }
    // Tile-parts: SOT (Lsot 10, Isot, Psot, TPsot, TNsot), Psot bytes from the SOT's first.
    while (size - at >= 2 && bigEndian(b + at, 2) == kSot) {
        if (size - at < 12 || bigEndian(b + at + 2, 2) != 10)
            return fail("tile-part header truncated or malformed");
        const uint32_t psot = bigEndian(b + at + 6, 4);
        // Psot 0 ("to the EOC") would let bytes after the real data pass as tile data.
        if (psot < 14 || psot > size - at)
            return fail("tile-part length (Psot) is 0 or runs past the codestream");
        at += psot;
    }
    if (size - at < 2 || bigEndian(b + at, 2) != kEoc)
        return fail("no EOC marker after the last tile-part");
    return at + 2;
}

bool htj2kDecodingAllowed()
{
    const char* v = std::getenv("RIDGE_ALLOW_HTJ2K");
    return v && std::string(v) == "1";
}

bool decode(Library library, const uint8_t* bytes, size_t size, int width, int height, int bits,
            int32_t* samples, std::string* error, bool trusted)
{
    if (library == Library::Htj2k && !trusted && !htj2kDecodingAllowed()) {
        *error = "HTJ2K decoding is off: OpenJPH 0.9 aborts the process on some malformed "
                 "codestreams (found by fuzzing); set RIDGE_ALLOW_HTJ2K=1 to build or read "
                 "HTJ2K archives you trust";
        return false;
    }
    if (width < 1 || height < 1 || bits < 1 || bits > 16) {
        *error = "invalid image";
        return false;
    }
    if (size == 0) {
        *error = "empty codestream";
        return false;
    }
    const bool ok = library == Library::Htj2k
                        ? decodeHtj2k(bytes, size, width, height, bits, samples, error)
                        : decodeOpenJpeg(bytes, size, width, height, bits, samples, error);
    if (!ok)
        return false;
    const int32_t top = (int32_t(1) << bits) - 1;
    const size_t count = size_t(width) * size_t(height);
    for (size_t i = 0; i < count; ++i)
        samples[i] = std::clamp(samples[i], int32_t(0), top);
    return true;
}

} // namespace ridge::j2k
