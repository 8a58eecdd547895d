#pragma once
// The streaming build (build_streaming.cpp): decimation, finest level first, in memory about
// a quarter of the grid.
#include "ridge/pipeline/build.h"

#include <optional>
#include <string>

namespace ridge {

// Builds `input` into `output` reading the finest level in strips. Returns nullopt, having
// written nothing, when the source has voids (filling them needs the whole grid) or the
// pyramid has a single level. For options with buildStreams(options) true.
std::optional<BuildReport> buildStreaming(const std::string& input, const std::string& output,
                                          const BuildOptions& options);

} // namespace ridge
