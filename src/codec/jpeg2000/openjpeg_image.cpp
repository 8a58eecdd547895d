// JPEG 2000 through OpenJPEG (j2k_image.h): in-memory opj_streams, first error kept.
#include "j2k_image.h"

#include <openjpeg.h>

#include <algorithm>
#include <cstring>
#include <memory>

namespace ridge::j2k {

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

void installHandlers(opj_codec_t* codec, std::string* first_error)
{
    opj_set_error_handler(codec, keepFirstError, first_error);
    opj_set_warning_handler(codec, ignoreMessage, nullptr);
    opj_set_info_handler(codec, ignoreMessage, nullptr);
}

bool fail(std::string* error, const std::string& what, const std::string& first)
{
    *error = what + (first.empty() ? "" : ": " + first);
    return false;
}

} // namespace

std::string openJpegVersion()
{
    return std::string("OpenJPEG ") + opj_version();
}

bool encodeOpenJpeg(const int32_t* samples, int width, int height, int bits, Rate rate,
                    std::vector<uint8_t>* out, std::string* error)
{
    opj_image_cmptparm_t component{};
    component.dx = component.dy = 1;
    component.w = OPJ_UINT32(width);
    component.h = OPJ_UINT32(height);
    component.prec = OPJ_UINT32(bits);
    component.sgnd = 0;
    ImagePtr image(opj_image_create(1, &component, OPJ_CLRSPC_GRAY));
    if (!image)
        return fail(error, "opj_image_create failed", {});
    image->x0 = image->y0 = 0;
    image->x1 = OPJ_UINT32(width);
    image->y1 = OPJ_UINT32(height);
    std::copy(samples, samples + size_t(width) * size_t(height), image->comps[0].data);

    opj_cparameters_t parameters;
    opj_set_default_encoder_parameters(&parameters);
    parameters.irreversible = rate.reversible ? 0 : 1;
    parameters.tcp_numlayers = 1;
    parameters.tcp_rates[0] = rate.reversible ? 0.f : float(std::max(1.0, rate.value));
    parameters.cp_disto_alloc = 1;
    parameters.numresolution = decompositionsFor(width, height) + 1;

    std::string first;
    CodecPtr codec(opj_create_compress(OPJ_CODEC_J2K));
    if (!codec)
        return fail(error, "opj_create_compress failed", {});
    installHandlers(codec.get(), &first);
    MemoryStream memory;
    StreamPtr stream(opj_stream_create(OPJ_J2K_STREAM_CHUNK_SIZE, OPJ_STREAM_WRITE));
    if (!stream)
        return fail(error, "opj_stream_create failed", {});
    opj_stream_set_user_data(stream.get(), &memory, nullptr);
    opj_stream_set_write_function(stream.get(), writeStream);
    opj_stream_set_skip_function(stream.get(), skipWrite);
    opj_stream_set_seek_function(stream.get(), seekWrite);
    const bool ok = opj_setup_encoder(codec.get(), &parameters, image.get()) &&
                    opj_start_compress(codec.get(), image.get(), stream.get()) &&
                    opj_encode(codec.get(), stream.get()) &&
                    opj_end_compress(codec.get(), stream.get());
    if (!ok)
        return fail(error, "OpenJPEG encode failed", first);
    stream.reset(); // flushes the remaining bytes into `memory`
    *out = std::move(memory.written);
    return true;
}

bool decodeOpenJpeg(const uint8_t* bytes, size_t size, int width, int height, int bits,
                    int32_t* samples, std::string* error)
{
    std::string first;
    CodecPtr codec(opj_create_decompress(OPJ_CODEC_J2K));
    if (!codec)
        return fail(error, "opj_create_decompress failed", {});
    installHandlers(codec.get(), &first);
    opj_dparameters_t parameters;
    opj_set_default_decoder_parameters(&parameters);
    MemoryStream memory;
    memory.source = bytes;
    memory.size = size;
    StreamPtr stream(opj_stream_create(OPJ_J2K_STREAM_CHUNK_SIZE, OPJ_STREAM_READ));
    if (!stream)
        return fail(error, "opj_stream_create failed", {});
    opj_stream_set_user_data(stream.get(), &memory, nullptr);
    opj_stream_set_user_data_length(stream.get(), size);
    opj_stream_set_read_function(stream.get(), readStream);
    opj_stream_set_skip_function(stream.get(), skipRead);
    opj_stream_set_seek_function(stream.get(), seekRead);

    opj_image_t* raw_image = nullptr;
    // Strict mode: a truncated codestream is an error, not a blurrier picture.
    const bool header = opj_setup_decoder(codec.get(), &parameters) &&
                        opj_decoder_set_strict_mode(codec.get(), OPJ_TRUE) &&
                        opj_read_header(stream.get(), codec.get(), &raw_image);
    ImagePtr image(raw_image);
    if (!header || !image)
        return fail(error, "bad JPEG 2000 header", first);
    const opj_image_comp_t& c = image->comps[0];
    if (image->numcomps != 1 || image->x0 != 0 || image->y0 != 0 || c.w != OPJ_UINT32(width) ||
        c.h != OPJ_UINT32(height) || c.dx != 1 || c.dy != 1 || c.sgnd != 0 ||
        c.prec != OPJ_UINT32(bits))
        return fail(error,
                    "the codestream is not one unsigned " + std::to_string(width) + "x" +
                        std::to_string(height) + " image of " + std::to_string(bits) + " bits",
                    {});
    if (!opj_decode(codec.get(), stream.get(), image.get()) ||
        !opj_end_decompress(codec.get(), stream.get()))
        return fail(error, "JPEG 2000 decode failed", first);
    const opj_image_comp_t& d = image->comps[0];
    if (!d.data || d.w != OPJ_UINT32(width) || d.h != OPJ_UINT32(height))
        return fail(error, "decoded image does not match the patch", {});
    std::copy(d.data, d.data + size_t(width) * size_t(height), samples);
    return true;
}

} // namespace ridge::j2k
