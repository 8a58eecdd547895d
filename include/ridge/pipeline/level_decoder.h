#pragma once
// Decoding a level (or a window of it) of an archive into a grid of codes.
#include "ridge/archive/archive_reader.h"
#include "ridge/core/progress.h"

#include <vector>

namespace ridge {

// Copies the n x n samples of `grid` at (x0, y0) into out[n·n]: a whole patch out of a
// decoded level, e.g. the parent a progressive codec predicts from.
void copyPatchFromGrid(const CodeGrid& grid, int x0, int y0, int n, uint16_t* out);

// Whole patches [px0, px1] x [py0, py1] of one level, decoded into one grid whose origin is
// sample (px0·cells, py0·cells) of the level. Whole patches, padding included, because a
// progressive codec predicts a child from every sample of its parent.
struct DecodedPatches {
    int level = 0;
    int px0 = 0, py0 = 0, px1 = -1, py1 = -1;
    CodeGrid grid;
    // When asked for: 1 where the sample is data (archive validity masks), same layout as
    // `grid`; empty when every sample of the range is data.
    std::vector<uint8_t> valid;
    // When asked for: each sample's flags (archive sample flags: kSampleWater, kSampleFilled),
    // same layout; empty when no sample of the range has one (or the archive stores none).
    std::vector<uint8_t> flags;

    // Copies patch `p` (inside the range) into out[n·n].
    void copyPatch(PatchId p, int n, uint16_t* out) const;
};

// Decodes patches [px0, px1] x [py0, py1] of `level` (clamped to the level), in parallel.
// When the codec predicts from parents, the covering patches of every coarser level are
// decoded first, top-down, each once. Throws ridge::Error for a corrupt patch.
// `with_validity`: also fill DecodedPatches::valid from the patches' validity masks;
// `with_flags`: DecodedPatches::flags from their sample flags.
DecodedPatches decodePatches(const archive::ArchiveReader& reader, int level, int px0, int py0,
                             int px1, int py1, const Progress& progress = {},
                             bool with_validity = false, bool with_flags = false);

// Decodes the samples [x0, x0+width) x [y0, y0+height) of `level` (level sample units; the
// window may reach into the padding up to geometry.levelWidth/levelHeight). Reads only the
// patches the window touches. Throws ridge::Error for a bad window or a corrupt patch.
// `valid`, when given, receives 1 where a sample is data, 0 where the archive keeps nodata
// (width·height entries, or empty when every sample of the window is data). `flags`, when
// given, receives the samples' flags likewise (empty when none has one).
CodeGrid decodeLevelWindow(const archive::ArchiveReader& reader, int level, int x0, int y0,
                           int width, int height, const Progress& progress = {},
                           std::vector<uint8_t>* valid = nullptr,
                           std::vector<uint8_t>* flags = nullptr);

// The samples of `level` inside the valid extent (validLevelWidth x validLevelHeight).
CodeGrid decodeLevel(const archive::ArchiveReader& reader, int level,
                     const Progress& progress = {});

// Heights in metres of a decoded grid, row-major (float: what GeoTIFF and shading consume).
std::vector<float> toMetres(const CodeGrid& grid, const HeightQuantization& quantization);

// `level`, or the finest level when `level` < 0.
int resolveLevel(const archive::ArchiveReader& reader, int level);

} // namespace ridge
