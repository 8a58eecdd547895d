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

uint32_t be(const uint8_t* p, int bytes)
{
    uint32_t v = 0;
    for (int k = 0; k < bytes; ++k)
        v = v << 8 | p[k];
    return v;
}

// OpenJPH 0.9 asserts (aborts the process) on some inconsistent main headers — fuzzing found
// a QCD with fewer subbands than COD's decompositions — so nothing reaches it that is not
// exactly the main header ridge writes: SIZ of one unsigned width x height component of
// `bits` in one tile, COD with the expected decompositions, 64x64 blocks, one layer, no
// precincts, no colour transform, and a QCD whose size matches its subbands; CAP and COM
// may appear, nothing else before the first SOT. Returns the problem, or empty.
std::string checkMainHeader(const uint8_t* b, size_t size, int width, int height, int bits)
{
    if (size < 4 || be(b, 2) != 0xFF4F)
        return "no SOC marker";
    size_t at = 2;
    int siz = 0, cod = 0, qcd = 0, decompositions = -1, reversible = -1;
    while (true) {
        if (at + 4 > size)
            return "main header truncated";
        const uint32_t marker = be(b + at, 2);
        if (marker == 0xFF90)
            break; // SOT: the tile-parts follow
        const uint32_t length = be(b + at + 2, 2);
        if (length < 2 || at + 2 + length > size)
            return "marker segment runs past the codestream";
        const uint8_t* m = b + at + 4;
        const size_t n = length - 2;
        if (marker == 0xFF51) {
            ++siz;
            if (n != 39 || be(m + 2, 4) != uint32_t(width) || be(m + 6, 4) != uint32_t(height) ||
                be(m + 10, 4) != 0 || be(m + 14, 4) != 0 || be(m + 18, 4) < uint32_t(width) ||
                be(m + 22, 4) < uint32_t(height) || be(m + 26, 4) != 0 || be(m + 30, 4) != 0 ||
                be(m + 34, 2) != 1 || m[36] != uint8_t(bits - 1) || m[37] != 1 || m[38] != 1)
                return "SIZ is not one unsigned " + std::to_string(width) + "x" +
                       std::to_string(height) + " component of " + std::to_string(bits) + " bits";
        } else if (marker == 0xFF52) {
            ++cod;
            if (n != 10 || m[0] != 0 || be(m + 2, 2) != 1 || m[4] != 0 ||
                m[5] != decompositionsFor(width, height) || m[6] != 4 || m[7] != 4 || m[9] > 1)
                return "COD is not the coding style ridge writes";
            decompositions = m[5];
            reversible = m[9];
        } else if (marker == 0xFF5C) {
            ++qcd;
            if (decompositions < 0)
                return "QCD before COD";
            const size_t subbands = 3 * size_t(decompositions) + 1;
            const int style = m[0] & 0x1f;
            const size_t expected = reversible ? 1 + subbands : 1 + 2 * subbands;
            if ((reversible && style != 0) || (!reversible && style != 2) || n != expected)
                return "QCD does not match COD's subbands";
        } else if (marker != 0xFF50 && marker != 0xFF64) {
            return "unexpected marker in the main header";
        }
        at += 2 + length;
    }
    if (siz != 1 || cod != 1 || qcd != 1)
        return "main header lacks SIZ, COD or QCD, or repeats one";
    return {};
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
    if (std::string problem = checkMainHeader(bytes, size, width, height, bits); !problem.empty()) {
        *error = "HTJ2K codestream refused: " + problem;
        return false;
    }
    try {
        ojph::mem_infile file;
        file.open(bytes, size);
        ojph::codestream stream;
        stream.read_headers(&file);
        ojph::param_siz siz = stream.access_siz();
        const ojph::point extent = siz.get_image_extent(), offset = siz.get_image_offset();
        const ojph::point sub =
            siz.get_num_components() == 1 ? siz.get_downsampling(0) : ojph::point(0, 0);
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
