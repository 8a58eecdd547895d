// JPEG-LS (ISO/IEC 14495-1) near-lossless through CharLS: LOCO-I prediction with context
// modelling, residuals quantized to step 2 NEAR + 1 inside the prediction loop, so the bound
// holds by construction. It is the standard's own answer to an L-inf bound.
#include "ridge/codecbench/anchor_codec.h"

#include "uniform_quantizer.h"

#include <charls/charls.h>

#include <fmt/core.h>

#include <algorithm>

namespace ridge::codecbench {

namespace {

// NEAR is an 8-bit field of the scan header and at most MAXVAL / 2 (T.87 C.2.4.1.1).
constexpr int kMaxNear = 255;

// The smallest precision that holds the tile: MAXVAL sets the context thresholds and the
// modular range, so a 9-bit tile coded as 16-bit would be coded worse than the standard
// allows.
int precisionOf(const uint16_t* codes, size_t count)
{
    const uint16_t max_code = count ? *std::max_element(codes, codes + count) : 0;
    return std::max(2, bitsFor(max_code));
}

class JpegLsAnchor final : public AnchorCodec {
  public:
    std::string name() const override { return "JPEG-LS"; }
    std::string description() const override
    {
        return "NEAR = min(e, 255, MAXVAL/2), one grey component, precision = bits of the "
               "tile's largest code, default thresholds";
    }
    std::string libraryVersion() const override
    {
        return std::string("CharLS ") + charls_get_version_string();
    }

    std::vector<uint8_t> encode(const uint16_t* codes, int width, int height,
                                int max_error) const override
    {
        const size_t count = size_t(width) * size_t(height);
        const int bits = precisionOf(codes, count);
        const int near = std::min({max_error, kMaxNear, ((1 << bits) - 1) / 2});
        try {
            charls::jpegls_encoder encoder;
            encoder.frame_info({uint32_t(width), uint32_t(height), bits, 1})
                .near_lossless(near)
                .encoding_options(charls::encoding_options::none);
            std::vector<uint8_t> stream(encoder.estimated_destination_size());
            encoder.destination(stream);
            // CharLS takes samples of up to 8 bits as bytes.
            if (bits <= 8) {
                const std::vector<uint8_t> narrow(codes, codes + count);
                stream.resize(encoder.encode(narrow.data(), narrow.size()));
            } else {
                stream.resize(encoder.encode(codes, count * sizeof(uint16_t)));
            }
            return stream;
        } catch (const charls::jpegls_error& e) {
            anchorFail(name(), std::string("encode failed: ") + e.what());
        }
    }

    void decode(const uint8_t* bytes, size_t size, int width, int height, int /*max_error*/,
                uint16_t* codes) const override
    {
        // A complete stream ends with the EOI marker, which bit stuffing keeps out of the
        // entropy-coded data. Checking it first matters: CharLS 2.4 spends seconds on some
        // truncated scans before it reports them.
        if (size < 2 || bytes[size - 2] != 0xFF || bytes[size - 1] != 0xD9)
            anchorFail(name(), "truncated stream (no end-of-image marker)");
        try {
            charls::jpegls_decoder decoder(bytes, size, true);
            const charls::frame_info& f = decoder.frame_info();
            if (f.width != uint32_t(width) || f.height != uint32_t(height) ||
                f.component_count != 1 || f.bits_per_sample < 2 || f.bits_per_sample > 16)
                anchorFail(name(), fmt::format("stream describes {}x{}, {} components of {} bits, "
                                               "expected {}x{} grey",
                                               f.width, f.height, f.component_count,
                                               f.bits_per_sample, width, height));
            const size_t count = size_t(width) * size_t(height);
            const size_t out_bytes = f.bits_per_sample <= 8 ? count : count * sizeof(uint16_t);
            if (decoder.destination_size() != out_bytes)
                anchorFail(name(), "stream needs " + std::to_string(decoder.destination_size()) +
                                       " output bytes, expected " + std::to_string(out_bytes));
            if (f.bits_per_sample <= 8) {
                std::vector<uint8_t> narrow(count);
                decoder.decode(narrow.data(), narrow.size());
                std::copy(narrow.begin(), narrow.end(), codes);
            } else {
                decoder.decode(codes, out_bytes);
            }
        } catch (const charls::jpegls_error& e) {
            anchorFail(name(), std::string("decode failed: ") + e.what());
        }
    }
};

} // namespace

std::unique_ptr<AnchorCodec> makeJpegLsAnchor()
{
    return std::make_unique<JpegLsAnchor>();
}

} // namespace ridge::codecbench
