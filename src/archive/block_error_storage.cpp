#include "ridge/archive/block_error_storage.h"

#include "ridge/archive/format.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <zstd.h>

namespace ridge::archive {

std::vector<uint8_t> packBlockErrors(const float* lambda_codes, size_t count, double height_scale)
{
    float largest = 0.f;
    for (size_t i = 0; i < count; ++i)
        largest = std::max(largest, lambda_codes[i]);
    // 65533 leaves room for the rounding margin below: the largest value never reaches
    // kBlockErrorSaturated.
    const float quantum = floatUp(std::max(height_scale / 16.0, largest * height_scale / 65533.0));
    std::vector<uint8_t> raw(2 * count);
    for (size_t i = 0; i < count; ++i) {
        // (1 + 1e-6) absorbs the float rounding of λ so that rounding up stays conservative.
        const double units =
            std::ceil(lambda_codes[i] * height_scale / double(quantum) * (1 + 1e-6));
        const uint16_t q =
            units >= kBlockErrorSaturated ? kBlockErrorSaturated : static_cast<uint16_t>(units);
        raw[2 * i] = static_cast<uint8_t>(q & 0xff);
        raw[2 * i + 1] = static_cast<uint8_t>(q >> 8);
    }
    std::vector<uint8_t> packed(4 + ZSTD_compressBound(raw.size()));
    std::memcpy(packed.data(), &quantum, 4); // little-endian hosts only (x86-64, arm64)
    const size_t n = ZSTD_compress(packed.data() + 4, packed.size() - 4, raw.data(), raw.size(), 3);
    packed.resize(ZSTD_isError(n) ? 0 : 4 + n);
    return packed;
}

bool unpackBlockErrors(const uint8_t* data, size_t size, size_t count, float* lambda_metres)
{
    if (size < 4)
        return false;
    float quantum;
    std::memcpy(&quantum, data, 4);
    if (!(quantum > 0.f) || !std::isfinite(quantum))
        return false;
    data += 4;
    size -= 4;
    if (ZSTD_getFrameContentSize(data, size) != 2 * count)
        return false;
    if (ZSTD_findFrameCompressedSize(data, size) != size)
        return false;
    std::vector<uint8_t> raw(2 * count);
    const size_t got = ZSTD_decompress(raw.data(), raw.size(), data, size);
    if (ZSTD_isError(got) || got != raw.size())
        return false;
    for (size_t i = 0; i < count; ++i) {
        const uint16_t q = static_cast<uint16_t>(raw[2 * i] | (raw[2 * i + 1] << 8));
        lambda_metres[i] = q == kBlockErrorSaturated ? std::numeric_limits<float>::infinity()
                                                     : floatUp(q * double(quantum));
    }
    return true;
}

} // namespace ridge::archive
