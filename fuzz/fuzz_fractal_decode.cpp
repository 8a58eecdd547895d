// libFuzzer target: the fractal patch decoder on arbitrary payloads. Byte 0 picks the patch
// size (2^n + 1, n = 2..7); the rest is the payload, decoded by a codec whose bound is the one
// the payload's header states (so that crafted bodies get past the header). Property: decode
// returns ok or a negative status, never reads or writes out of bounds (domain positions, s
// and o out of range, truncated or oversized zstd frames, corrections past the code range are
// all refused), and what decodes is what the attractor plus its corrections give.
#include "ridge/codec/fractal_codec.h"

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    if (size < 7)
        return 0;
    const int n = (1 << (2 + data[0] % 6)) + 1;
    const uint8_t* payload = data + 1;
    const size_t payload_size = size - 1;
    const int bound = int(payload[4] | payload[5] << 8);
    if (bound > 32767)
        return 0;
    // Flags byte 1 is the paper's mode (transforms alone): decoded by a codec in that mode.
    ridge::FractalVariant variant;
    variant.paper = payload[3] == 1;
    const ridge::FractalCodec codec(bound, 2, variant);
    const ridge::PatchContext ctx{n, 1, nullptr, 0, 0, 0};
    std::vector<uint16_t> out(size_t(n) * n), attractor(out.size());
    const int status = codec.decode(out.data(), payload, payload_size, ctx);
    if (status > 0)
        __builtin_trap(); // statuses are 0 or negative
    if (status == ridge::kCodecOk) {
        if (codec.decodeAttractor(attractor.data(), payload, payload_size, ctx, payload[2]) !=
            ridge::kCodecOk)
            __builtin_trap();
        // Edges are the attractor's pinned values; interior samples differ by whole steps.
        for (size_t i = 0; i < out.size(); ++i) {
            const int d = int(out[i]) - int(attractor[i]);
            if (variant.paper ? d != 0
                              : (d % (2 * bound + 1) != 0 && out[i] != 0 && out[i] != 65535))
                __builtin_trap();
        }
    }
    // The GPU decoder's CPU half: refuses or accepts exactly what decode() parses (decode may
    // refuse more: it checks the corrections against the attractor), with every field in range.
    std::shared_ptr<const ridge::GpuPayload> gpu;
    const int gpu_status = codec.decodeForGpu(payload, payload_size, ctx, &gpu);
    if (gpu_status > 0 || (status == ridge::kCodecOk && gpu_status != ridge::kCodecOk))
        __builtin_trap();
    if (gpu_status == ridge::kCodecOk) {
        const auto& f = static_cast<const ridge::FractalPayload&>(*gpu);
        const int ranges = (n + 3) / 4;
        if (f.transforms.size() != size_t(ranges) * ranges * 4 || f.samples.size() != out.size())
            __builtin_trap();
        for (size_t r = 0; r < f.transforms.size(); r += 4)
            if (f.transforms[r] < 0 || f.transforms[r] >= ranges - 1 || f.transforms[r + 1] < 0 ||
                f.transforms[r + 1] >= ranges - 1 || std::abs(f.transforms[r + 2]) > 24)
                __builtin_trap();
    }
    return 0;
}
