#include "ridge/plot/png_plot.h"

#include "ridge/core/error.h"

#include <plplot.h>

#include <filesystem>

namespace ridge::plot {
namespace {

constexpr const char* kDevice = "pngcairo";

bool deviceAvailable(const char* device)
{
    int count = 128;
    std::vector<const char*> menu(count), names(count);
    const char** menu_ptr = menu.data();
    const char** names_ptr = names.data();
    plgDevs(&menu_ptr, &names_ptr, &count);
    for (int i = 0; i < count; ++i)
        if (names[i] && std::string(names[i]) == device)
            return true;
    return false;
}

// Checked before the AtomicOutput exists, so that a missing device leaves no temporary file.
const std::string& checkedPath(const std::string& path)
{
    if (!deviceAvailable(kDevice))
        throw Error(path + ": PLplot has no '" + kDevice +
                    "' device (install plplot-driver-cairo)");
    return path;
}

} // namespace

PngPlot::PngPlot(const std::string& path, int width, int height, const std::vector<Rgb>& palette)
    : path_(path), output_(checkedPath(path))
{
    PLINT previous = 0, stream = 0;
    plgstrm(&previous);
    previous_stream_ = previous;
    plmkstrm(&stream);
    plsdev(kDevice);
    plsfnam(output_.temporaryPath().c_str());
    plsetopt("geometry", (std::to_string(width) + "x" + std::to_string(height)).c_str());
    plscmap0n(PLINT(palette.size()));
    for (size_t i = 0; i < palette.size(); ++i)
        plscol0(PLINT(i), palette[i][0], palette[i][1], palette[i][2]);
    plinit();
}

PngPlot::~PngPlot()
{
    end();
}

void PngPlot::end()
{
    if (ended_)
        return;
    ended_ = true;
    plend1();
    plsstrm(previous_stream_);
}

void PngPlot::commit()
{
    end();
    std::error_code ec;
    if (std::filesystem::file_size(output_.temporaryPath(), ec) == 0 || ec)
        throw Error(path_ + ": PLplot wrote no image");
    output_.commit();
}

std::string plplotText(const std::string& text)
{
    std::string out;
    for (const char c : text) {
        out += c;
        if (c == '#')
            out += '#';
    }
    return out;
}

} // namespace ridge::plot
