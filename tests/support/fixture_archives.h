#pragma once
// Archives of the bundled Everest fixture for tests that render or stream (they link
// ridge_pipeline): patches of 33 give its 301 x 203 samples 5 levels, an unbalanced tree and
// seams between patches up to 4 levels apart.
#include "test_support.h"

#include "ridge/codec/height_codec.h"
#include "ridge/pipeline/build.h"

#include <string>

#include <algorithm>

namespace ridge::test {

// Builds everest_crop.tif into `dir` with `codec` ("lossless", "progressive",
// "progressive-paper", "raw", "jpeg2000[,...]"); `max_error` in metres for the lossy codecs.
// Returns the path.
inline std::string buildEverestArchive(const ScratchDir& dir, const std::string& codec = "lossless",
                                       int patch_size = 33, double max_error = 2.0)
{
    BuildOptions options;
    options.patch_size = patch_size;
    options.codec = codec;
    if (isLossyCodec(codec))
        options.max_error = max_error;
    options.progress = {};
    std::string stem = codec;
    std::replace(stem.begin(), stem.end(), ',', '_');
    const std::string path = dir.path(stem + "_" + std::to_string(patch_size) + "_" +
                                      std::to_string(int(max_error * 10)) + ".ridge");
    buildArchive(dataPath("everest_crop.tif"), path, options);
    return path;
}

} // namespace ridge::test
