// libFuzzer target: the lossless patch decoder on arbitrary payloads.
// The first byte picks the patch size (2^n + 1, n = 2..7); the rest is the payload.
// Property: decode returns ok or a negative status, never reads or writes out of bounds.
#include "ridge/codec/lossless_codec.h"

#include <cstddef>
#include <cstdint>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    if (size < 1)
        return 0;
    const int n = (1 << (2 + data[0] % 6)) + 1;
    std::vector<uint16_t> out(static_cast<size_t>(n) * n);
    const ridge::LosslessCodec codec;
    const int status = codec.decode(out.data(), data + 1, size - 1, {n, 0, nullptr, 0});
    if (status > 0)
        __builtin_trap(); // statuses are 0 or negative
    if (status == ridge::kCodecOk) {
        // A payload that decodes must re-encode to something that decodes to the same codes.
        std::vector<uint8_t> again(codec.encodeBound({n, 0, nullptr, 0}));
        again.resize(codec.encode(again.data(), again.size(), out.data(), {n, 0, nullptr, 0}));
        std::vector<uint16_t> back(out.size());
        if (codec.decode(back.data(), again.data(), again.size(), {n, 0, nullptr, 0}) != 0 ||
            back != out)
            __builtin_trap();
    }
    return 0;
}
