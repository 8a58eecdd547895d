// JPEG 2000 as an anchor. JPEG 2000 has no L-inf mode of its own (its rate control bounds
// MSE, not the worst sample), so the tile is first quantized to step 2e+1 and the indices are
// coded losslessly with the reversible 5/3 wavelet: the strongest L-inf-bounded use of the
// standard. Codestream only (.j2k, no JP2 boxes), one quality layer, OpenJPEG defaults
// otherwise (64x64 code-blocks, LRCP, up to 6 resolutions).
#include "ridge/codecbench/anchor_codec.h"

#include "uniform_quantizer.h"

#include <openjpeg.h>

#include <fmt/core.h>

#include <algorithm>
#include <cstring>
#include <memory>

namespace ridge::codecbench {

namespace {

// In-memory codestream behind opj_stream callbacks: the encoder writes (and may seek back),
// the decoder reads untrusted bytes and may never see past `size`.
struct MemoryStream {
    std::vector<uint8_t> written;
    const uint8_t* source = nullptr;
    size_t size = 0;
    size_t position = 0;
};

OPJ_SIZE_T readStream(void* buffer, OPJ_SIZE_T bytes, void* user)
{
    auto* s = static_cast<MemoryStream*>(user);
    const size_t n = std::min<size_t>(bytes, s->size - s->position);
    if (n == 0)
        return static_cast<OPJ_SIZE_T>(-1); // end of stream, as opj_stream expects
    std::memcpy(buffer, s->source + s->position, n);
    s->position += n;
    return n;
}

OPJ_OFF_T skipRead(OPJ_OFF_T bytes, void* user)
{
    auto* s = static_cast<MemoryStream*>(user);
    if (bytes < 0)
        s->position -= std::min<size_t>(s->position, size_t(-bytes));
    else
        s->position += std::min<size_t>(size_t(bytes), s->size - s->position);
    return bytes;
}

OPJ_BOOL seekRead(OPJ_OFF_T offset, void* user)
{
    auto* s = static_cast<MemoryStream*>(user);
    if (offset < 0 || size_t(offset) > s->size)
        return OPJ_FALSE;
    s->position = size_t(offset);
    return OPJ_TRUE;
}

OPJ_SIZE_T writeStream(void* buffer, OPJ_SIZE_T bytes, void* user)
{
    auto* s = static_cast<MemoryStream*>(user);
    if (s->written.size() < s->position + bytes)
        s->written.resize(s->position + bytes);
    std::memcpy(s->written.data() + s->position, buffer, bytes);
    s->position += bytes;
    return bytes;
}

OPJ_OFF_T skipWrite(OPJ_OFF_T bytes, void* user)
{
    auto* s = static_cast<MemoryStream*>(user);
    if (bytes < 0 && size_t(-bytes) > s->position)
        return -1;
    s->position = size_t(OPJ_OFF_T(s->position) + bytes);
    if (s->written.size() < s->position)
        s->written.resize(s->position);
    return bytes;
}

OPJ_BOOL seekWrite(OPJ_OFF_T offset, void* user)
{
    auto* s = static_cast<MemoryStream*>(user);
    if (offset < 0)
        return OPJ_FALSE;
    s->position = size_t(offset);
    if (s->written.size() < s->position)
        s->written.resize(s->position);
    return OPJ_TRUE;
}

// OpenJPEG reports failures through callbacks; the first error becomes the Error message.
void keepFirstError(const char* message, void* user)
{
    auto* first = static_cast<std::string*>(user);
    if (first->empty() && message) {
        *first = message;
        while (!first->empty() && (first->back() == '\n' || first->back() == ' '))
            first->pop_back();
    }
}

void ignoreMessage(const char*, void*) {}

struct CodecDeleter {
    void operator()(opj_codec_t* c) const { opj_destroy_codec(c); }
};
struct StreamDeleter {
    void operator()(opj_stream_t* s) const { opj_stream_destroy(s); }
};
struct ImageDeleter {
    void operator()(opj_image_t* i) const { opj_image_destroy(i); }
};
using CodecPtr = std::unique_ptr<opj_codec_t, CodecDeleter>;
using StreamPtr = std::unique_ptr<opj_stream_t, StreamDeleter>;
using ImagePtr = std::unique_ptr<opj_image_t, ImageDeleter>;

// Each decomposition halves the smaller side; the lowest resolution must keep a sample.
int resolutionsFor(int width, int height)
{
    const int smaller = std::min(width, height);
    int levels = 1;
    while (levels < 6 && (smaller >> levels) > 0)
        ++levels;
    return levels;
}

void installHandlers(opj_codec_t* codec, std::string* first_error)
{
    opj_set_error_handler(codec, keepFirstError, first_error);
    opj_set_warning_handler(codec, ignoreMessage, nullptr);
    opj_set_info_handler(codec, ignoreMessage, nullptr);
}

class Jpeg2000Anchor final : public AnchorCodec {
  public:
    std::string name() const override { return "JPEG 2000"; }
    std::string description() const override
    {
        return "quantize to step 2e+1, then lossless OpenJPEG: reversible 5/3, one layer, "
               "codestream only, up to 6 resolutions, 64x64 code-blocks, precision = bits of "
               "the largest index";
    }
    std::string libraryVersion() const override { return std::string("OpenJPEG ") + opj_version(); }

    std::vector<uint8_t> encode(const uint16_t* codes, int width, int height,
                                int max_error) const override
    {
        const size_t count = size_t(width) * size_t(height);
        const std::vector<uint16_t> q = quantizeCodes(codes, count, max_error);
        const uint16_t max_q = count ? *std::max_element(q.begin(), q.end()) : 0;

        opj_image_cmptparm_t component{};
        component.dx = component.dy = 1;
        component.w = OPJ_UINT32(width);
        component.h = OPJ_UINT32(height);
        component.prec = OPJ_UINT32(bitsFor(max_q));
        component.sgnd = 0;
        ImagePtr image(opj_image_create(1, &component, OPJ_CLRSPC_GRAY));
        if (!image)
            anchorFail(name(), "opj_image_create failed");
        image->x0 = image->y0 = 0;
        image->x1 = OPJ_UINT32(width);
        image->y1 = OPJ_UINT32(height);
        std::copy(q.begin(), q.end(), image->comps[0].data);

        opj_cparameters_t parameters;
        opj_set_default_encoder_parameters(&parameters);
        parameters.irreversible = 0; // 5/3 integer wavelet: lossless
        parameters.tcp_numlayers = 1;
        parameters.tcp_rates[0] = 0; // 0 = lossless layer
        parameters.cp_disto_alloc = 1;
        parameters.numresolution = resolutionsFor(width, height);

        std::string error;
        CodecPtr codec(opj_create_compress(OPJ_CODEC_J2K));
        if (!codec)
            anchorFail(name(), "opj_create_compress failed");
        installHandlers(codec.get(), &error);
        MemoryStream memory;
        StreamPtr stream(opj_stream_create(OPJ_J2K_STREAM_CHUNK_SIZE, OPJ_STREAM_WRITE));
        if (!stream)
            anchorFail(name(), "opj_stream_create failed");
        opj_stream_set_user_data(stream.get(), &memory, nullptr);
        opj_stream_set_write_function(stream.get(), writeStream);
        opj_stream_set_skip_function(stream.get(), skipWrite);
        opj_stream_set_seek_function(stream.get(), seekWrite);
        const bool ok = opj_setup_encoder(codec.get(), &parameters, image.get()) &&
                        opj_codec_set_threads(codec.get(), 0) &&
                        opj_start_compress(codec.get(), image.get(), stream.get()) &&
                        opj_encode(codec.get(), stream.get()) &&
                        opj_end_compress(codec.get(), stream.get());
        if (!ok)
            anchorFail(name(), "encode failed: " + (error.empty() ? "no message" : error));
        stream.reset(); // flushes the remaining bytes into `memory`
        return std::move(memory.written);
    }

    void decode(const uint8_t* bytes, size_t size, int width, int height, int max_error,
                uint16_t* codes) const override
    {
        std::string error;
        CodecPtr codec(opj_create_decompress(OPJ_CODEC_J2K));
        if (!codec)
            anchorFail(name(), "opj_create_decompress failed");
        installHandlers(codec.get(), &error);
        opj_dparameters_t parameters;
        opj_set_default_decoder_parameters(&parameters);
        MemoryStream memory;
        memory.source = bytes;
        memory.size = size;
        StreamPtr stream(opj_stream_create(OPJ_J2K_STREAM_CHUNK_SIZE, OPJ_STREAM_READ));
        if (!stream)
            anchorFail(name(), "opj_stream_create failed");
        opj_stream_set_user_data(stream.get(), &memory, nullptr);
        opj_stream_set_user_data_length(stream.get(), size);
        opj_stream_set_read_function(stream.get(), readStream);
        opj_stream_set_skip_function(stream.get(), skipRead);
        opj_stream_set_seek_function(stream.get(), seekRead);

        opj_image_t* raw_image = nullptr;
        // Strict mode: a truncated codestream is an error, not a blurrier picture.
        bool ok = opj_setup_decoder(codec.get(), &parameters) &&
                  opj_decoder_set_strict_mode(codec.get(), OPJ_TRUE) &&
                  opj_codec_set_threads(codec.get(), 0) &&
                  opj_read_header(stream.get(), codec.get(), &raw_image);
        ImagePtr image(raw_image);
        if (ok) {
            const opj_image_comp_t& c = image->comps[0];
            if (image->numcomps != 1 || c.w != OPJ_UINT32(width) || c.h != OPJ_UINT32(height) ||
                c.dx != 1 || c.dy != 1 || c.sgnd != 0)
                anchorFail(name(), fmt::format("codestream describes {} components, {}x{}, "
                                               "expected one unsigned {}x{}",
                                               image->numcomps, c.w, c.h, width, height));
            ok = opj_decode(codec.get(), stream.get(), image.get()) &&
                 opj_end_decompress(codec.get(), stream.get());
        }
        if (!ok)
            anchorFail(name(), "decode failed: " + (error.empty() ? "no message" : error));
        const opj_image_comp_t& c = image->comps[0];
        if (!c.data || c.w != OPJ_UINT32(width) || c.h != OPJ_UINT32(height))
            anchorFail(name(), "decoded image does not match the tile");
        const int64_t max_q = maxQuantizedCode(max_error);
        const size_t count = size_t(width) * size_t(height);
        for (size_t i = 0; i < count; ++i) {
            const OPJ_INT32 v = c.data[i];
            if (v < 0 || v > max_q)
                anchorFail(name(), fmt::format("decoded index {} out of range 0..{}", v, max_q));
            codes[i] = dequantizeCode(uint32_t(v), max_error);
        }
    }
};

} // namespace

std::unique_ptr<AnchorCodec> makeJpeg2000Anchor()
{
    return std::make_unique<Jpeg2000Anchor>();
}

} // namespace ridge::codecbench
