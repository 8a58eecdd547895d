// libFuzzer target: the progressive patch decoder (entropy decoding + reconstruction).
// Input: byte 0 picks the patch size (2^n + 1, n = 2..7) and (bits 4..7) how much of the
// patch covers the valid extent, byte 1 the level (0..3) and quadrant, byte 2 the bound
// (0..31 codes) and variant (v1's four, v2, v3 or v4 with 1, 2 or 32 nested levels and either
// predictor), byte 3 seeds the parent and (bits 6..7: 0 v2, 1 v3, 2 or 3 v4) picks the payload
// version; the rest is the payload. v2..v4 decode with their default tables (an archive's own
// tables are fuzzed through the archive target). Properties: decode returns ok or a negative status
// and stays in bounds; a patch that decodes re-encodes, from the same parent, to a payload decoding
// to what the codec says it reconstructs.
#include "ridge/codec/progressive_codec.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    if (size < 4)
        return 0;
    const int n = (1 << (2 + data[0] % 6)) + 1;
    const int level = data[1] & 3, child = (data[1] >> 2) & 3;
    const int pick = data[2] >> 5;
    ridge::ProgressiveVariant variant = ridge::ProgressiveVariant::v1();
    if (pick < 4)
        variant = *ridge::ProgressiveVariant::fromBits(pick << 1);
    else
        variant = {pick & 1 ? ridge::OddPredictor::Cubic : ridge::OddPredictor::Bilinear, true,
                   std::min(2 + (data[3] >> 6), 4), pick < 6 ? pick - 3 : 32};
    const ridge::ProgressiveCodec codec((data[2] & 31) * 0.75, 4, variant);
    std::vector<uint16_t> parent(static_cast<size_t>(n) * n), out(parent.size());
    uint32_t state = data[3] * 2654435761u + 1;
    for (uint16_t& v : parent) { // a rough but deterministic parent
        state = state * 1664525u + 1013904223u;
        v = static_cast<uint16_t>(20000 + (state >> 22));
    }
    const int cut = data[0] >> 4; // samples covering the extent: all (0) or fewer
    const ridge::PatchContext ctx{n,
                                  level,
                                  level > 0 ? parent.data() : nullptr,
                                  child,
                                  cut ? 1 + (cut * (n - 1)) / 16 : 0,
                                  cut ? n - cut % 4 : 0};
    const int status = codec.decode(out.data(), data + 4, size - 4, ctx);
    if (status > 0)
        __builtin_trap();
    if (status == ridge::kCodecOk) {
        std::vector<uint8_t> again(codec.encodeBound(ctx));
        again.resize(codec.encode(again.data(), again.size(), out.data(), ctx));
        std::vector<uint16_t> expected(out.size()), back(out.size());
        codec.reconstruct(out.data(), ctx, expected.data());
        if (again.empty() || codec.decode(back.data(), again.data(), again.size(), ctx) != 0 ||
            back != expected)
            __builtin_trap();
    }
    return 0;
}
