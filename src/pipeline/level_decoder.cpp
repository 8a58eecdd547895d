#include "ridge/pipeline/level_decoder.h"

#include "ridge/core/error.h"

#include <algorithm>
#include <exception>
#include <string>

namespace ridge {

CodeGrid decodeLevelWindow(const archive::ArchiveReader& reader, int level, int x0, int y0,
                           int width, int height, const Progress& progress,
                           std::vector<uint8_t>* valid, std::vector<uint8_t>* flags)
{
    const PyramidGeometry& g = reader.geometry();
    if (level < 0 || level >= g.levelCount())
        throw Error(reader.path() + ": level " + std::to_string(level) +
                    " does not exist (levels 0.." + std::to_string(g.levelCount() - 1) + ")");
    if (x0 < 0 || y0 < 0 || width <= 0 || height <= 0 ||
        int64_t{x0} + width > g.levelWidth(level) || int64_t{y0} + height > g.levelHeight(level))
        throw Error(reader.path() + ": window " + std::to_string(x0) + "," + std::to_string(y0) +
                    " " + std::to_string(width) + "x" + std::to_string(height) +
                    " is outside level " + std::to_string(level) + " (" +
                    std::to_string(g.validLevelWidth(level)) + "x" +
                    std::to_string(g.validLevelHeight(level)) + ")");

    const int cells = g.cells();
    const DecodedPatches patches =
        decodePatches(reader, level, x0 / cells, y0 / cells, (x0 + width - 1) / cells,
                      (y0 + height - 1) / cells, progress, valid != nullptr, flags != nullptr);
    CodeGrid grid;
    grid.width = width;
    grid.height = height;
    grid.codes.resize(static_cast<size_t>(width) * height);
    const int gx = x0 - patches.px0 * cells, gy = y0 - patches.py0 * cells;
    for (int j = 0; j < height; ++j)
        std::copy_n(patches.grid.codes.data() + static_cast<size_t>(gy + j) * patches.grid.width +
                        gx,
                    width, &grid.at(0, j));
    // The window of a per-sample byte plane of `patches`; empty when it is all `uniform`.
    auto window = [&](const std::vector<uint8_t>& plane, uint8_t uniform,
                      std::vector<uint8_t>& out) {
        out.clear();
        if (plane.empty())
            return;
        out.resize(grid.codes.size());
        for (int j = 0; j < height; ++j)
            std::copy_n(plane.data() + static_cast<size_t>(gy + j) * patches.grid.width + gx, width,
                        out.data() + static_cast<size_t>(j) * width);
        if (std::all_of(out.begin(), out.end(), [&](uint8_t v) { return v == uniform; }))
            out.clear();
    };
    if (valid)
        window(patches.valid, 1, *valid);
    if (flags)
        window(patches.flags, 0, *flags);
    return grid;
}

void copyPatchFromGrid(const CodeGrid& grid, int x0, int y0, int n, uint16_t* out)
{
    for (int j = 0; j < n; ++j)
        std::copy_n(grid.codes.data() + static_cast<size_t>(y0 + j) * grid.width + x0, n,
                    out + static_cast<size_t>(j) * n);
}

void DecodedPatches::copyPatch(PatchId p, int n, uint16_t* out) const
{
    const int cells = n - 1;
    copyPatchFromGrid(grid, (p.x - px0) * cells, (p.y - py0) * cells, n, out);
}

DecodedPatches decodePatches(const archive::ArchiveReader& reader, int level, int px0, int py0,
                             int px1, int py1, const Progress& progress, bool with_validity,
                             bool with_flags)
{
    const PyramidGeometry& g = reader.geometry();
    const int n = g.patchSize(), cells = g.cells();
    DecodedPatches out;
    out.level = level;
    out.px0 = std::clamp(px0, 0, g.patchesX(level) - 1);
    out.py0 = std::clamp(py0, 0, g.patchesY(level) - 1);
    out.px1 = std::clamp(px1, out.px0, g.patchesX(level) - 1);
    out.py1 = std::clamp(py1, out.py0, g.patchesY(level) - 1);
    const int nx = out.px1 - out.px0 + 1, ny = out.py1 - out.py0 + 1;

    // The parents first: the coarser level's patches covering this range.
    DecodedPatches parents;
    const bool needs_parent = reader.codec().needsParent(level);
    if (needs_parent)
        parents = decodePatches(reader, level - 1, out.px0 / 2, out.py0 / 2, out.px1 / 2,
                                out.py1 / 2, subProgress(progress, 0.0, 0.25));

    out.grid.width = nx * cells + 1;
    out.grid.height = ny * cells + 1;
    out.grid.codes.resize(static_cast<size_t>(out.grid.width) * out.grid.height);
    // Version 1 archives have no masks: every sample is data.
    if (with_validity && reader.storesValidity())
        out.valid.assign(out.grid.codes.size(), 1);
    if (with_flags && reader.storesSampleFlags())
        out.flags.assign(out.grid.codes.size(), 0);
    bool any_invalid = false, any_flag = false;
    std::exception_ptr failure;
#pragma omp parallel
    {
        std::vector<uint16_t> patch(static_cast<size_t>(n) * n), parent;
        if (needs_parent)
            parent.resize(patch.size());
#pragma omp for schedule(dynamic, 1)
        for (int64_t k = 0; k < int64_t{nx} * ny; ++k) {
            const PatchId p{level, out.px0 + static_cast<int>(k % nx),
                            out.py0 + static_cast<int>(k / nx)};
            PatchValidity validity;
            PatchSampleFlags flags;
            try {
                if (needs_parent)
                    parents.copyPatch(p.parent(), n, parent.data());
                const std::vector<uint8_t> blob = reader.readBlob(p);
                reader.decodeBlob(p, blob, patch.data(), needs_parent ? parent.data() : nullptr,
                                  nullptr, out.valid.empty() ? nullptr : &validity,
                                  out.flags.empty() ? nullptr : &flags);
            } catch (...) {
#pragma omp critical
                failure = std::current_exception();
                continue;
            }
            // Neighbours write the same shared-border values, so the overlap is benign;
            // still, each patch writes only its own cells plus the far border on the last.
            const int gx = (p.x - out.px0) * cells, gy = (p.y - out.py0) * cells;
            const int w = p.x == out.px1 ? n : cells, h = p.y == out.py1 ? n : cells;
            for (int j = 0; j < h; ++j)
                std::copy_n(patch.data() + static_cast<size_t>(j) * n, w, &out.grid.at(gx, gy + j));
            // The patch's own w × h samples of a per-sample byte plane of the grid. Shared
            // borders: a patch's masks agree with its neighbours' on them (both come from
            // the level's one grid).
            auto writePlane = [&](std::vector<uint8_t>& plane, auto byteOf) {
                for (int j = 0; j < h; ++j)
                    for (int i = 0; i < w; ++i)
                        plane[static_cast<size_t>(gy + j) * out.grid.width + gx + i] = byteOf(i, j);
            };
            if (!out.valid.empty() && validity.kind != PatchValidity::Kind::AllValid) {
                writePlane(out.valid,
                           [&](int i, int j) -> uint8_t { return validity.sampleValid(i, j); });
#pragma omp atomic write
                any_invalid = true;
            }
            if (!out.flags.empty() && flags.kind != PatchSampleFlags::Kind::None) {
                writePlane(out.flags, [&](int i, int j) { return flags.at(i, j); });
#pragma omp atomic write
                any_flag = true;
            }
        }
    }
    if (failure)
        std::rethrow_exception(failure);
    if (!any_invalid)
        out.valid.clear();
    if (!any_flag)
        out.flags.clear();
    reportProgress(progress, 1.0);
    return out;
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
