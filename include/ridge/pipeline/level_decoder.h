#pragma once
// Decoding a level (or a window of it) of an archive into a grid of codes.
#include "ridge/archive/archive_reader.h"
#include "ridge/core/progress.h"

#include <vector>

namespace ridge {

// Decodes the samples [x0, x0+width) x [y0, y0+height) of `level` (level sample units; the
// window may reach into the padding up to geometry.levelWidth/levelHeight). Reads only the
// patches the window touches. Throws ridge::Error for a bad window or a corrupt patch.
CodeGrid decodeLevelWindow(const archive::ArchiveReader& reader, int level, int x0, int y0,
                           int width, int height, const Progress& progress = {});

// The samples of `level` inside the valid extent (validLevelWidth x validLevelHeight).
CodeGrid decodeLevel(const archive::ArchiveReader& reader, int level, const Progress& progress = {});

// Heights in metres of a decoded grid, row-major (float: what GeoTIFF and shading consume).
std::vector<float> toMetres(const CodeGrid& grid, const HeightQuantization& quantization);

// `level`, or the finest level when `level` < 0.
int resolveLevel(const archive::ArchiveReader& reader, int level);

} // namespace ridge
