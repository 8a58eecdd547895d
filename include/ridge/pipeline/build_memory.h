#pragma once
// What `buildArchive` will hold in memory at its peak, estimated from the raster's declared
// size before anything is allocated, so that a raster the machine cannot build is refused with
// a message (file, W x H, memory needed, memory available) instead of dying in bad_alloc
// after minutes of work.
//
// Terms (W x H samples, n = C + 1 samples per patch side, P patches over all levels):
//   streaming (decimation, void-free source; docs/DESIGN.md "Build pipeline"):
//     level L-1 in memory      levelWidth(L-1) · levelHeight(L-1) · 2 B   (≈ W·H/2 B)
//     source strip             (2C+1) · W · (2 B + extra B), extra = 8 B of doubles for
//                              non-integer types, 1 B of mask; plus GDAL's block cache
//     index and errors         P · (48 B writer record + 48 B serialised index + 12 B
//                              PatchErrors + 1 bit written flag)
//     encode batches           kEncodeBatchPatches patches of n² · 2 B codes + payload
//                              (+ reconstruction, lossy) + per-thread patch buffers
//     progressive              reconstructions of two consecutive levels up to L−1 (the
//       reconstructions        finest is coded from level L−1's codes)
//   in memory (Neville filter, jpeg2000, voids): the largest of three phases
//     ingest                   whole grid W·H·2 B; with voids (found, or possible: the band
//                              declares nodata or a mask) a 1 B/sample mask and
//                              GDALFillNodata's work rasters (5 B/sample of at most 16 M
//                              samples; larger windows go to temporary files); strips of
//                              source values and GDAL's block cache
//     Neville coarsening       whole grid; the row pass into floats (H · levelWidth(L-1) · 4 B,
//                              as much as the grid) and level L-1 being made
//                              voids kept as nodata (fill_voids interior/none): + 1 B/sample
//                              (the flood fill's stack, 8 B per border-connected void, is
//                              not counted)
//     build                    whole grid; Neville levels (Σ coarser levels · 2 B ≈ ⅓ grid);
//                              kept nodata: its mask and the validity grids (W·H + 2·Σ levels
//                              bits ≈ 1.33 B/sample);
//                              index and errors; progressive reconstructions kept for the
//                              children (the widest two consecutive levels' patches, n² · 2 B
//                              each); encode batches
//   both: kBaselineBytes for the program, GDAL, PROJ and thread stacks.
// Checked against the peak RSS (/usr/bin/time -v) of real builds on 2 cores: the estimate is
// 10-35% above it (the baseline is rounded up; void filling is counted whenever the band
// declares nodata, as nearly every DEM does, though its mask is only made at the first void).
#include "ridge/core/system_memory.h"
#include "ridge/io/raster_source.h"
#include "ridge/pipeline/build.h"

#include <cstdint>
#include <string>
#include <vector>

namespace ridge {

// Patches encoded in parallel before being written in order (build.cpp).
inline constexpr int64_t kEncodeBatchPatches = 64;
// The program itself: code, GDAL and PROJ state, OpenMP thread stacks (the peak RSS of
// building the 301 x 203 Everest fixture is 55 MiB, most of it this).
inline constexpr uint64_t kBaselineBytes = uint64_t{64} << 20;

struct MemoryTerm {
    std::string what; // "level L-1 in memory"
    uint64_t bytes = 0;
};

struct BuildMemoryEstimate {
    bool streaming = false;
    std::vector<MemoryTerm> terms; // those of the peak, largest first

    uint64_t total() const;
    // "streaming: level L-1 in memory, 466 GiB; index and errors, 8.20 GiB; ..." (terms under
    // 0.1% of the total are left out; they are in total()).
    std::string describe() const;
};

// True when buildArchive tries the streaming path first: decimation, and a codec that may
// encode the finest level first (codecBuildsFinestFirst: lossless, progressive).
bool buildStreams(const BuildOptions& options);

// The estimate for `raster` built with `options` on the streaming path or in memory; `voids`:
// the in-memory path fills voids (the streaming path found some, or the band declares
// nodata or a mask and may have them). Throws ridge::Error for a patch size
// PyramidGeometry refuses.
BuildMemoryEstimate estimateBuildMemory(const io::RasterProbe& raster, const BuildOptions& options,
                                        bool streaming, bool voids);

// The memory the build may use: options.memory_limit_bytes when set (source
// "memory_limit_bytes"), else availableMemory().
AvailableMemory buildMemoryLimit(const BuildOptions& options);

// Throws ridge::Error("INPUT: W x H samples need about X to build (PATH: TERMS), but Y are
// available (SOURCE); ...") when the estimate exceeds `limit`.
void checkBuildMemory(const std::string& input, const io::RasterProbe& raster,
                      const BuildMemoryEstimate& estimate, const AvailableMemory& limit);

} // namespace ridge
