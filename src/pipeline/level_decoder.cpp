#include "ridge/pipeline/level_decoder.h"

#include "ridge/core/error.h"

#include <algorithm>
#include <string>

namespace ridge {

CodeGrid decodeLevelWindow(const archive::ArchiveReader& reader, int level, int x0, int y0,
                           int width, int height, const Progress& progress)
{
    const PyramidGeometry& g = reader.geometry();
    if (level < 0 || level >= g.levelCount())
        throw Error(reader.path() + ": level " + std::to_string(level) + " does not exist (levels 0.." +
                    std::to_string(g.levelCount() - 1) + ")");
    if (x0 < 0 || y0 < 0 || width <= 0 || height <= 0 ||
        int64_t{x0} + width > g.levelWidth(level) || int64_t{y0} + height > g.levelHeight(level))
        throw Error(reader.path() + ": window " + std::to_string(x0) + "," + std::to_string(y0) +
                    " " + std::to_string(width) + "x" + std::to_string(height) +
                    " is outside level " + std::to_string(level) + " (" +
                    std::to_string(g.validLevelWidth(level)) + "x" +
                    std::to_string(g.validLevelHeight(level)) + ")");

    CodeGrid grid;
    grid.width = width;
    grid.height = height;
    grid.codes.resize(static_cast<size_t>(width) * height);
    const int cells = g.cells();
    const int n = g.patchSize();
    const int px0 = x0 / cells, px1 = std::min((x0 + width - 1) / cells, g.patchesX(level) - 1);
    const int py0 = y0 / cells, py1 = std::min((y0 + height - 1) / cells, g.patchesY(level) - 1);
    std::vector<uint16_t> patch(static_cast<size_t>(n) * n);
    for (int py = py0; py <= py1; ++py) {
        for (int px = px0; px <= px1; ++px) {
            reader.decodePatch({level, px, py}, patch.data());
            // Copy the part of the patch inside the window.
            const int ia = std::max(x0, px * cells), ib = std::min(x0 + width - 1, px * cells + cells);
            const int ja = std::max(y0, py * cells), jb = std::min(y0 + height - 1, py * cells + cells);
            for (int j = ja; j <= jb; ++j)
                for (int i = ia; i <= ib; ++i)
                    grid.at(i - x0, j - y0) = patch[static_cast<size_t>(j - py * cells) * n + (i - px * cells)];
        }
        reportProgress(progress, double(py - py0 + 1) / double(py1 - py0 + 1));
    }
    return grid;
}

CodeGrid decodeLevel(const archive::ArchiveReader& reader, int level, const Progress& progress)
{
    const PyramidGeometry& g = reader.geometry();
    if (level < 0 || level >= g.levelCount())
        return decodeLevelWindow(reader, level, 0, 0, 1, 1, progress); // throws the message
    return decodeLevelWindow(reader, level, 0, 0, g.validLevelWidth(level),
                             g.validLevelHeight(level), progress);
}

std::vector<float> toMetres(const CodeGrid& grid, const HeightQuantization& quantization)
{
    std::vector<float> metres(grid.codes.size());
    for (size_t i = 0; i < metres.size(); ++i)
        metres[i] = static_cast<float>(quantization.toMetres(grid.codes[i]));
    return metres;
}

int resolveLevel(const archive::ArchiveReader& reader, int level)
{
    return level < 0 ? reader.geometry().finestLevel() : level;
}

} // namespace ridge
