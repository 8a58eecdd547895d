#pragma once
// Semantic checks of a parsed .ridge index (docs/FORMAT.md, "Index entry"), run by
// ArchiveReader when it opens an archive: the CRC only proves the bytes are what a writer
// wrote, these prove they mean something a renderer can use (finite, ordered, nested bounds;
// blobs that tile the patch area).
//
// Each returns "" or the first problem, naming the entry: "index entry 3, patch (level 1,
// x 0, y 1): min_height 12 > max_height 3". The archive path is the caller's to prepend.
#include "ridge/archive/format.h"

#include <string>
#include <vector>

namespace ridge::archive {

// What the checks know of the archive besides its records.
struct IndexContext {
    const Header& header; // checked by parseHeader
    const PyramidGeometry& geometry;
    std::vector<double> level_bound; // δ_l in metres, per level (ArchiveReader::levelErrorBound)
};

// Entry i alone: position (level, x, y), blob extent and sizes, heights and error bounds.
std::string checkIndexEntry(const IndexContext& ctx, int64_t i, const PatchRecord& r);
// Parent against children: min/max cover every descendant, Err_Appr(P) >= Err_Appr(child).
// Cost O(patches).
std::string checkIndexHierarchy(const IndexContext& ctx, const std::vector<PatchRecord>& records);
// The blobs tile [kHeaderSize, metadata_offset) exactly: no overlap, no byte outside a blob.
// Cost O(n log n).
std::string checkBlobTiling(const IndexContext& ctx, const std::vector<PatchRecord>& records);

} // namespace ridge::archive
