#pragma once
// One PLplot page rendered to a PNG with the pngcairo device (headless, anti-aliased text),
// written atomically: the benches' plots (codec-bench rate-distortion, bench frame times).
//
// PLplot keeps global state per stream and calls exit() on a fatal error, so a page runs on
// a stream of its own, checks that the device exists before plinit (which would otherwise
// prompt on stdin for another one), and restores the caller's stream when it ends. Not
// thread-safe. Between construction and commit() the caller draws with plain pl* calls.
#include "ridge/core/atomic_output.h"

#include <array>
#include <string>
#include <vector>

namespace ridge::plot {

class PngPlot {
  public:
    using Rgb = std::array<int, 3>;
    // Starts a `width`×`height` page for `path` with `palette` as cmap0 (colour 0 is the
    // background). Throws ridge::Error naming `path` when PLplot has no pngcairo device.
    PngPlot(const std::string& path, int width, int height, const std::vector<Rgb>& palette);
    // Ends the stream; without commit() nothing is left at `path`.
    ~PngPlot();
    PngPlot(const PngPlot&) = delete;
    PngPlot& operator=(const PngPlot&) = delete;

    // Ends the page and moves the PNG into place; throws if PLplot wrote nothing.
    void commit();

  private:
    void end();

    std::string path_;
    AtomicOutput output_;
    int previous_stream_ = 0;
    bool ended_ = false;
};

// `text` with PLplot's escape character ('#') doubled, for labels from user data.
std::string plplotText(const std::string& text);

} // namespace ridge::plot
