#pragma once
// `ridge bench ARCHIVE --bytes-per-view`: the bytes a cold cache reads to draw each frame of a
// camera path (stream::viewBytes on the renderer's own selection), GL-free — selection only,
// nothing decoded but the root patch (the paths' ground heights, as the renderer's). Not part
// of libridge.
//
// The path is exactly ridge bench's: lod::makeCameraPath with the ground and clip planes of
// lod::CoarseTerrain from the root patch, a 60° vertical field of view, the options'
// viewport. The selection is the tessellation scheme's (stream::rendererSelectionSettings with
// the options' ε, texel_px, culling and side-on bound; no slot budget). Summary "near / mid /
// far" are the path's first, middle (frames / 2) and last frames — on the fly-over the first
// and last frames sit 300 m over the terrain, so read them as positions along the path, not
// as stream::TypicalView's definitions (codec-bench reports those).
#include "ridge/renderbench/render_bench.h"

#include <cstdint>
#include <string>
#include <vector>

namespace ridge::renderbench {

struct ViewBytesFrameRecord {
    glm::dvec3 position{0.0}; // camera, terrain frame, metres
    uint64_t bytes = 0;       // cold cache: selected patches (and ancestors, see report)
    uint64_t patches = 0;     // distinct patches read
    uint64_t selected = 0;    // patches drawn
};

struct ViewBytesBenchReport {
    std::string archive;
    RenderBenchOptions options;
    std::string codec;               // the archive's codec name
    bool counts_ancestors = false;   // the codec needs ancestors: they are counted once per frame
    uint64_t archive_blob_bytes = 0; // every blob of the archive
    std::vector<ViewBytesFrameRecord> frames;
    // Summary over the frames.
    uint64_t bytes_min = 0, bytes_median = 0, bytes_max = 0;
    double bytes_mean = 0.0;
    // Every frame's patches together: what a cache that never evicts reads along the path.
    uint64_t path_bytes = 0;
    uint64_t path_patches = 0;
    // Frames 0, frames/2 and frames−1 (see above).
    size_t near_frame = 0, mid_frame = 0, far_frame = 0;
};

// Throws ridge::Error for options RenderBenchOptions::validate refuses (before the archive is
// opened), naming the archive or the path file on bad input. Cost: one root decode, then one
// selection (a few µs to ms) per frame; no GL context.
ViewBytesBenchReport runViewBytesBench(const std::string& archive,
                                       const RenderBenchOptions& options);
// Human summary: settings, the three frames, min / median / max, the whole path.
std::string formatViewBytesSummary(const ViewBytesBenchReport& report);
// Every frame's figures and the summary as a JSON document (ends with a newline).
std::string formatViewBytesJson(const ViewBytesBenchReport& report);
// Writes formatViewBytesJson to `path` atomically. Throws ridge::Error naming the path.
void writeViewBytesJson(const ViewBytesBenchReport& report, const std::string& path);

} // namespace ridge::renderbench
