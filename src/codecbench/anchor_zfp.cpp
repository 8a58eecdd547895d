// ZFP as an anchor: the compressed floating-point format of scientific computing, whose
// fixed-accuracy mode is the usual answer to "compress this field to within tolerance t".
// The tolerance only sets the lowest bit plane coded (2^floor(log2 t)); ZFP's decorrelating
// transform is not orthogonal, so the bound is a target the library usually meets, not a
// guarantee. The bench measures every sample and reports what ZFP really does.
//
// This work is based on:
//   P. Lindstrom, "Fixed-Rate Compressed Floating-Point Arrays", IEEE TVCG 20(12), 2014.
//
// The tile is coded as float (16-bit codes are exact in float); decoded values are rounded
// to the nearest code, which keeps any |error| <= e (e an integer). e = 0 uses ZFP's
// reversible (lossless) mode. The stream has no ZFP header: dimensions and tolerance come
// from the container, as with the MED+zstd anchor.
#include "ridge/codecbench/anchor_codec.h"

#include "uniform_quantizer.h"

#include <zfp.h>

#include <fmt/core.h>

#include <cmath>
#include <cstring>
#include <memory>

namespace ridge::codecbench {

namespace {

struct FieldDeleter {
    void operator()(zfp_field* f) const { zfp_field_free(f); }
};
struct StreamDeleter {
    void operator()(zfp_stream* s) const { zfp_stream_close(s); }
};
struct BitstreamDeleter {
    void operator()(bitstream* b) const { stream_close(b); }
};

// A zfp stream configured for `max_error`, serial execution.
std::unique_ptr<zfp_stream, StreamDeleter> openStream(int max_error)
{
    std::unique_ptr<zfp_stream, StreamDeleter> zfp(zfp_stream_open(nullptr));
    if (!zfp)
        return zfp;
    if (max_error == 0)
        zfp_stream_set_reversible(zfp.get());
    else
        zfp_stream_set_accuracy(zfp.get(), double(max_error));
    zfp_stream_set_execution(zfp.get(), zfp_exec_serial);
    return zfp;
}

// One compression or decompression: the float field over `values`, a stream for
// `max_error`, and a bit stream over `words` (zfp reads and writes whole 64-bit words).
struct ZfpSession {
    std::unique_ptr<zfp_field, FieldDeleter> field;
    std::unique_ptr<zfp_stream, StreamDeleter> zfp;
    std::unique_ptr<bitstream, BitstreamDeleter> bits;

    ZfpSession(const std::string& anchor, float* values, int width, int height, int max_error)
        : field(zfp_field_2d(values, zfp_type_float, size_t(width), size_t(height))),
          zfp(openStream(max_error))
    {
        if (!field || !zfp)
            anchorFail(anchor, "zfp setup failed");
    }
    size_t maximumSize() const { return zfp_stream_maximum_size(zfp.get(), field.get()); }
    void attach(const std::string& anchor, std::vector<uint64_t>& words)
    {
        bits.reset(stream_open(words.data(), words.size() * sizeof(uint64_t)));
        if (!bits)
            anchorFail(anchor, "stream_open failed");
        zfp_stream_set_bit_stream(zfp.get(), bits.get());
        zfp_stream_rewind(zfp.get());
    }
};

class ZfpAnchor final : public AnchorCodec {
  public:
    std::string name() const override { return "ZFP"; }
    std::string description() const override
    {
        return "fixed-accuracy mode, tolerance = e, tile as float, decoded values rounded to "
               "codes; reversible mode for e = 0; no ZFP header";
    }
    std::string libraryVersion() const override { return std::string("zfp ") + ZFP_VERSION_STRING; }
    bool guaranteesBound() const override { return false; }

    std::vector<uint8_t> encode(const uint16_t* codes, int width, int height,
                                int max_error) const override
    {
        const size_t count = size_t(width) * size_t(height);
        std::vector<float> values(codes, codes + count);
        ZfpSession session(name(), values.data(), width, height, max_error);
        std::vector<uint64_t> words((session.maximumSize() + 7) / 8);
        session.attach(name(), words);
        const size_t size = zfp_compress(session.zfp.get(), session.field.get());
        if (size == 0)
            anchorFail(name(), "zfp_compress failed");
        std::vector<uint8_t> stream(size);
        std::memcpy(stream.data(), words.data(), size);
        return stream;
    }

    void decode(const uint8_t* bytes, size_t size, int width, int height, int max_error,
                uint16_t* codes) const override
    {
        const size_t count = size_t(width) * size_t(height);
        std::vector<float> values(count);
        ZfpSession session(name(), values.data(), width, height, max_error);
        // ZFP reads without bounds checks; a copy padded with zeros to the largest stream this
        // configuration can produce keeps a truncated or corrupt stream inside the buffer.
        const size_t capacity = std::max(size, session.maximumSize());
        std::vector<uint64_t> words((capacity + 7) / 8 + 1, 0);
        std::memcpy(words.data(), bytes, size);
        session.attach(name(), words);
        const size_t consumed = zfp_decompress(session.zfp.get(), session.field.get());
        if (consumed == 0)
            anchorFail(name(), "zfp_decompress failed");
        // The encoder's size is exactly what decoding consumes: anything else is a truncated
        // stream (consumed > size) or one that is not what it claims to be.
        if (consumed != size)
            anchorFail(name(), fmt::format("stream of {} bytes decodes {} bytes", size, consumed));
        for (size_t i = 0; i < count; ++i) {
            const float v = values[i];
            if (!std::isfinite(v))
                anchorFail(name(), "decoded a non-finite value");
            codes[i] = static_cast<uint16_t>(std::lround(std::clamp(v, 0.0f, 65535.0f)));
        }
    }
};

} // namespace

std::unique_ptr<AnchorCodec> makeZfpAnchor()
{
    return std::make_unique<ZfpAnchor>();
}

} // namespace ridge::codecbench
