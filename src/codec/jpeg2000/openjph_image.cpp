// HTJ2K through OpenJPH (j2k_image.h). OpenJPH reports failures by calling its error
// handler, which throws; ours throws without printing, and every call is wrapped so that a
// corrupt codestream becomes `false` plus the library's message.
#include "j2k_image.h"

#include <openjph/ojph_arch.h> // defines OJPH_EXPORT, which the other headers use
#include <openjph/ojph_codestream.h>
#include <openjph/ojph_file.h>
#include <openjph/ojph_mem.h>
#include <openjph/ojph_message.h>
#include <openjph/ojph_params.h>
#include <openjph/ojph_version.h>

#include <cstdarg>
#include <cstdio>
#include <mutex>
#include <stdexcept>

namespace ridge::j2k {

namespace {

class ThrowQuietly final : public ojph::message_error {
  public:
    void operator()(int, const char*, int, const char* fmt, ...) override
    {
        char text[256];
        va_list args;
        va_start(args, fmt);
        std::vsnprintf(text, sizeof text, fmt, args);
        va_end(args);
        throw std::runtime_error(text);
    }
};

class Ignore final : public ojph::message_warning {
  public:
    void operator()(int, const char*, int, const char*, ...) override {}
};

class IgnoreInfo final : public ojph::message_info {
  public:
    void operator()(int, const char*, int, const char*, ...) override {}
};

// OpenJPH's handlers are process-wide; installed once, before the first use.
void installHandlers()
{
    static std::once_flag once;
    std::call_once(once, [] {
        static ThrowQuietly error;
        static Ignore warning;
        static IgnoreInfo info;
        ojph::configure_error(&error);
        ojph::configure_warning(&warning);
        ojph::configure_info(&info);
    });
}

} // namespace

std::string htj2kVersion()
{
    return "OpenJPH " + std::to_string(OPENJPH_VERSION_MAJOR) + "." +
           std::to_string(OPENJPH_VERSION_MINOR) + "." + std::to_string(OPENJPH_VERSION_PATCH);
}

bool encodeHtj2k(const int32_t* samples, int width, int height, int bits, Rate rate,
                 std::vector<uint8_t>* out, std::string* error)
{
    installHandlers();
    try {
        ojph::codestream stream;
        ojph::param_siz siz = stream.access_siz();
        siz.set_image_extent(ojph::point(ojph::ui32(width), ojph::ui32(height)));
        siz.set_num_components(1);
        siz.set_component(0, ojph::point(1, 1), ojph::ui32(bits), false);
        ojph::param_cod cod = stream.access_cod();
        cod.set_num_decomposition(ojph::ui32(decompositionsFor(width, height)));
        cod.set_block_dims(64, 64);
        cod.set_color_transform(false);
        cod.set_reversible(rate.reversible);
        if (!rate.reversible)
            stream.access_qcd().set_irrev_quant(float(rate.value));
        stream.set_planar(false);
        ojph::mem_outfile file;
        file.open();
        stream.write_headers(&file);
        ojph::ui32 component = 0;
        ojph::line_buf* line = stream.exchange(nullptr, component);
        for (int y = 0; y < height; ++y) {
            const int32_t* row = samples + size_t(y) * size_t(width);
            for (int x = 0; x < width; ++x)
                line->i32[x] = row[x];
            line = stream.exchange(line, component);
        }
        stream.flush();
        out->assign(file.get_data(), file.get_data() + file.tell());
        stream.close();
        return true;
    } catch (const std::exception& e) {
        *error = std::string("OpenJPH encode failed: ") + e.what();
        return false;
    }
}

bool decodeHtj2k(const uint8_t* bytes, size_t size, int width, int height, int bits,
                 int32_t* samples, std::string* error)
{
    installHandlers();
    try {
        ojph::mem_infile file;
        file.open(bytes, size);
        ojph::codestream stream;
        stream.read_headers(&file);
        ojph::param_siz siz = stream.access_siz();
        const ojph::point extent = siz.get_image_extent(), offset = siz.get_image_offset();
        const ojph::point sub = siz.get_num_components() == 1 ? siz.get_downsampling(0)
                                                              : ojph::point(0, 0);
        if (siz.get_num_components() != 1 || extent.x != ojph::ui32(width) ||
            extent.y != ojph::ui32(height) || offset.x != 0 || offset.y != 0 || sub.x != 1 ||
            sub.y != 1 || siz.is_signed(0) || siz.get_bit_depth(0) != ojph::ui32(bits)) {
            *error = "the codestream is not one unsigned " + std::to_string(width) + "x" +
                     std::to_string(height) + " image of " + std::to_string(bits) + " bits";
            return false;
        }
        stream.set_planar(false);
        stream.create();
        for (int y = 0; y < height; ++y) {
            ojph::ui32 component = 0;
            ojph::line_buf* line = stream.pull(component);
            if (!line || component != 0 || line->size < size_t(width))
                throw std::runtime_error("short image line");
            int32_t* row = samples + size_t(y) * size_t(width);
            for (int x = 0; x < width; ++x)
                row[x] = line->i32[x];
        }
        stream.close();
        return true;
    } catch (const std::exception& e) {
        *error = std::string("HTJ2K decode failed: ") + e.what();
        return false;
    }
}

} // namespace ridge::j2k
