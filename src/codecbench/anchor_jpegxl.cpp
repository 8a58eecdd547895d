// JPEG XL as an anchor. Like JPEG 2000 it has no L-inf mode (its lossy modes bound a
// perceptual distance), so the tile is quantized to step 2e+1 and the indices are coded with
// lossless modular JPEG XL: MA-tree context modelling over a choice of predictors, which is
// the state of the art for lossless 16-bit grey. Bare codestream (no container), no parallel
// runner (single-threaded), at a given effort: 7 is cjxl's default, 9 the strongest libjxl 0.7
// offers (tortoise: far slower to encode, decoding barely changes).
//
// Progressive ("responsive", cjxl -R 1): the modular image goes through JPEG XL's squeeze
// transform, a reversible Haar-like pyramid whose coarse levels the codestream holds first,
// finer ones refining them, as in ridge's pyramid. So this row prices progressiveness in the
// strongest anchor: the same lossless coder, only the transform differs. (libjxl 0.7 does not
// show a preview of a one-group tile from a prefix, JxlDecoderFlushImage refuses; the format
// allows it, and larger images keep their coarse levels in the global section.)
#include "ridge/codecbench/anchor_codec.h"

#include "uniform_quantizer.h"

#include "ridge/core/parameter_check.h"

#include <jxl/decode.h>
#include <jxl/encode.h>

#include <fmt/core.h>

#include <algorithm>
#include <memory>

namespace ridge::codecbench {

namespace {

struct EncoderDeleter {
    void operator()(JxlEncoder* e) const { JxlEncoderDestroy(e); }
};
struct DecoderDeleter {
    void operator()(JxlDecoder* d) const { JxlDecoderDestroy(d); }
};

// libjxl 0.7 (Debian 12) aborts the process at efforts 8 and 9 on images of fewer than about
// 100 samples (JXL_DASSERT "n <= 255" in enc_ans.cc, a trap, not an error status: 1 x 1,
// 11 x 9, flat 7 x 14 measured; 10 x 10 and up passed). Such tiles — a bench's thin edge
// strips — are coded at effort 7 instead, with a margin: their bytes are noise in any row.
constexpr int kMaxSafeSmallImageEffort = 7;
constexpr size_t kMinSamplesForHighEffort = 256;

// The indices travel as 16-bit grey: q < 2^16 for every e, and 16-bit samples pass through
// lossless JPEG XL unchanged.
constexpr JxlPixelFormat kGrey16{1, JXL_TYPE_UINT16, JXL_NATIVE_ENDIAN, 0};

std::string versionString(uint32_t v)
{
    return fmt::format("{}.{}.{}", v / 1000000, v / 1000 % 1000, v % 1000);
}

class JpegXlAnchor final : public AnchorCodec {
  public:
    JpegXlAnchor(int effort, bool progressive) : effort_(effort), progressive_(progressive) {}
    // One row per effort and mode: "JPEG XL e7", "JPEG XL e9", "JPEG XL e9 progressive".
    std::string name() const override
    {
        return fmt::format("JPEG XL e{}{}", effort_, progressive_ ? " progressive" : "");
    }
    std::string description() const override
    {
        return fmt::format("quantize to step 2e+1, then lossless libjxl (modular{}), effort {}, "
                           "16-bit grey, original profile, bare codestream{}",
                           progressive_ ? ", responsive: squeezed into a lossless pyramid" : "",
                           effort_,
                           effort_ > kMaxSafeSmallImageEffort
                               ? fmt::format(" (tiles under {} samples at effort {}: libjxl 0.7 "
                                             "aborts on them)",
                                             kMinSamplesForHighEffort, kMaxSafeSmallImageEffort)
                               : std::string());
    }
    std::string libraryVersion() const override
    {
        return "libjxl " + versionString(JxlEncoderVersion());
    }
    bool progressive() const override { return progressive_; }

    std::vector<uint8_t> encode(const uint16_t* codes, int width, int height,
                                int max_error) const override
    {
        const size_t count = size_t(width) * size_t(height);
        const std::vector<uint16_t> q = quantizeCodes(codes, count, max_error);

        std::unique_ptr<JxlEncoder, EncoderDeleter> encoder(JxlEncoderCreate(nullptr));
        if (!encoder)
            anchorFail(name(), "JxlEncoderCreate failed");
        JxlBasicInfo info;
        JxlEncoderInitBasicInfo(&info);
        info.xsize = uint32_t(width);
        info.ysize = uint32_t(height);
        info.bits_per_sample = 16;
        info.num_color_channels = 1;
        info.uses_original_profile = JXL_TRUE; // no XYB: samples are coded as given
        JxlColorEncoding colour;
        JxlColorEncodingSetToLinearSRGB(&colour, /*is_gray=*/JXL_TRUE);
        check(JxlEncoderSetBasicInfo(encoder.get(), &info), encoder.get(),
              "JxlEncoderSetBasicInfo");
        check(JxlEncoderSetColorEncoding(encoder.get(), &colour), encoder.get(),
              "JxlEncoderSetColorEncoding");
        JxlEncoderFrameSettings* settings = JxlEncoderFrameSettingsCreate(encoder.get(), nullptr);
        if (!settings)
            anchorFail(name(), "JxlEncoderFrameSettingsCreate failed");
        check(JxlEncoderSetFrameLossless(settings, JXL_TRUE), encoder.get(),
              "JxlEncoderSetFrameLossless");
        const int effort = count < kMinSamplesForHighEffort
                               ? std::min(effort_, kMaxSafeSmallImageEffort)
                               : effort_;
        check(JxlEncoderFrameSettingsSetOption(settings, JXL_ENC_FRAME_SETTING_EFFORT, effort),
              encoder.get(), "effort");
        // Stated either way (libjxl's default, -1, chooses by effort and lossiness; for these
        // lossless frames it chose 0, byte for byte).
        check(JxlEncoderFrameSettingsSetOption(settings, JXL_ENC_FRAME_SETTING_RESPONSIVE,
                                               progressive_ ? 1 : 0),
              encoder.get(), "responsive");
        check(JxlEncoderAddImageFrame(settings, &kGrey16, q.data(), q.size() * sizeof(uint16_t)),
              encoder.get(), "JxlEncoderAddImageFrame");
        JxlEncoderCloseInput(encoder.get());

        std::vector<uint8_t> stream(4096 + count / 2);
        size_t used = 0;
        for (;;) {
            uint8_t* next = stream.data() + used;
            size_t avail = stream.size() - used;
            const JxlEncoderStatus status = JxlEncoderProcessOutput(encoder.get(), &next, &avail);
            used = size_t(next - stream.data());
            if (status == JXL_ENC_SUCCESS)
                break;
            if (status != JXL_ENC_NEED_MORE_OUTPUT)
                check(status, encoder.get(), "JxlEncoderProcessOutput");
            stream.resize(stream.size() * 2);
        }
        stream.resize(used);
        return stream;
    }

    void decode(const uint8_t* bytes, size_t size, int width, int height, int max_error,
                uint16_t* codes) const override
    {
        std::unique_ptr<JxlDecoder, DecoderDeleter> decoder(JxlDecoderCreate(nullptr));
        if (!decoder)
            anchorFail(name(), "JxlDecoderCreate failed");
        if (JxlDecoderSubscribeEvents(decoder.get(), JXL_DEC_BASIC_INFO | JXL_DEC_FULL_IMAGE) !=
                JXL_DEC_SUCCESS ||
            JxlDecoderSetInput(decoder.get(), bytes, size) != JXL_DEC_SUCCESS)
            anchorFail(name(), "decoder setup failed");
        JxlDecoderCloseInput(decoder.get());

        const size_t count = size_t(width) * size_t(height);
        std::vector<uint16_t> q(count);
        bool have_image = false;
        for (;;) {
            const JxlDecoderStatus status = JxlDecoderProcessInput(decoder.get());
            if (status == JXL_DEC_BASIC_INFO) {
                JxlBasicInfo info;
                if (JxlDecoderGetBasicInfo(decoder.get(), &info) != JXL_DEC_SUCCESS)
                    anchorFail(name(), "unreadable basic info");
                if (info.xsize != uint32_t(width) || info.ysize != uint32_t(height) ||
                    info.num_color_channels != 1 || info.bits_per_sample != 16)
                    anchorFail(name(),
                               fmt::format("stream describes {}x{}, {} channels of {} bits, "
                                           "expected {}x{} 16-bit grey",
                                           info.xsize, info.ysize, info.num_color_channels,
                                           info.bits_per_sample, width, height));
            } else if (status == JXL_DEC_NEED_IMAGE_OUT_BUFFER) {
                size_t needed = 0;
                if (JxlDecoderImageOutBufferSize(decoder.get(), &kGrey16, &needed) !=
                        JXL_DEC_SUCCESS ||
                    needed != q.size() * sizeof(uint16_t) ||
                    JxlDecoderSetImageOutBuffer(decoder.get(), &kGrey16, q.data(), needed) !=
                        JXL_DEC_SUCCESS)
                    anchorFail(name(), "output buffer does not match the tile");
            } else if (status == JXL_DEC_FULL_IMAGE) {
                have_image = true;
            } else if (status == JXL_DEC_SUCCESS) {
                break;
            } else if (status == JXL_DEC_NEED_MORE_INPUT) {
                anchorFail(name(), "truncated stream");
            } else {
                anchorFail(name(), fmt::format("decode failed (status {})", int(status)));
            }
        }
        if (!have_image)
            anchorFail(name(), "stream holds no image");
        const uint32_t max_q = maxQuantizedCode(max_error);
        for (size_t i = 0; i < count; ++i) {
            if (q[i] > max_q)
                anchorFail(name(), fmt::format("decoded index {} out of range 0..{}", q[i], max_q));
            codes[i] = dequantizeCode(q[i], max_error);
        }
    }

  private:
    int effort_;
    bool progressive_;

    void check(JxlEncoderStatus status, JxlEncoder* encoder, const char* step) const
    {
        if (status != JXL_ENC_SUCCESS)
            anchorFail(name(), fmt::format("{} failed (encoder error {})", step,
                                           int(JxlEncoderGetError(encoder))));
    }
};

} // namespace

std::unique_ptr<AnchorCodec> makeJpegXlAnchor(int effort, bool progressive)
{
    checkParameter("JPEG XL effort", int64_t{effort}, 1, 9);
    return std::make_unique<JpegXlAnchor>(effort, progressive);
}

} // namespace ridge::codecbench
