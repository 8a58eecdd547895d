// libFuzzer target: the jpeg2000 patch decoder (OpenJPEG and OpenJPH underneath) on
// arbitrary payloads. Byte 0 picks the patch size (2^n + 1, n = 2..7); byte 1: bit 0 the
// level (0 root, 1 a child with a synthetic parent), bits 1..2 the quadrant, bit 3 HTJ2K (refused:
// RIDGE_ALLOW_HTJ2K is not set here, OpenJPH 0.9 aborts on malformed input), bit 4 a clipped
// region; the rest is the payload. Property: decode returns ok or a negative status, never reads or
// writes out of bounds, and what decodes is within the code range (uint16 by type) and equals
// difference + prediction.
#include "ridge/codec/jpeg2000_codec.h"

#include <cstddef>
#include <cstdint>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    if (size < 2)
        return 0;
    const int n = (1 << (2 + data[0] % 6)) + 1;
    const int level = data[1] & 1;
    ridge::Jpeg2000Variant v;
    v.library = (data[1] & 8) ? ridge::Jpeg2000Library::Htj2k : ridge::Jpeg2000Library::OpenJpeg;
    const ridge::Jpeg2000Codec codec(2, 2, v);
    std::vector<uint16_t> parent(size_t(n) * n);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
            parent[size_t(y) * n + x] = uint16_t(30000 + 37 * x - 23 * y);
    const int clip = (data[1] & 16) ? n / 2 + 1 : 0;
    const ridge::PatchContext ctx{n,    level, level ? parent.data() : nullptr, (data[1] >> 1) & 3,
                                  clip, clip};
    std::vector<uint16_t> out(size_t(n) * n);
    const int status = codec.decode(out.data(), data + 2, size - 2, ctx);
    if (status > 0)
        __builtin_trap(); // statuses are 0 or negative
    if (status == ridge::kCodecOk) {
        ridge::Jpeg2000Difference d;
        if (codec.decodeDifference(data + 2, size - 2, ctx, &d) != ridge::kCodecOk)
            __builtin_trap();
        std::vector<uint16_t> again(out.size());
        ridge::Jpeg2000Codec::addPrediction(d, ctx, again.data());
        if (again != out)
            __builtin_trap();
    }
    return 0;
}
