#include "index_checks.h"

#include "ridge/archive/archive_reader.h"
#include "ridge/core/parameter_check.h"

#include <algorithm>
#include <cfloat>
#include <charconv>
#include <cmath>
#include <numeric>

namespace ridge::archive {

namespace {

// The smallest block-error region: the f32 quantum, then the smallest zstd frame that holds
// content and states its size: 4-byte magic, frame header descriptor, 1-byte content size,
// 3-byte block header, 1 byte of an RLE block.
constexpr uint32_t kMinBlockErrorsSize = 4 + 10;

// A bound as messages print it: the shortest text that reads back as the same number, as an
// f32 when it is one (index fields are f32; their double spelling is noise).
std::string number(double v)
{
    if (std::isfinite(v) && std::fabs(v) <= FLT_MAX && double(float(v)) == v) {
        char text[32];
        const auto end = std::to_chars(text, text + sizeof text, float(v)).ptr;
        return std::string(text, end);
    }
    return formatNumber(v);
}

std::string entryName(int64_t i, PatchId p)
{
    return "index entry " + std::to_string(i) + ", " + ArchiveReader::patchName(p);
}

// "[lo, hi]" (appended to a std::string: GCC 12 warns falsely on "[" + temporary).
std::string range(double lo, double hi)
{
    std::string text = "[";
    text += number(lo);
    text += ", ";
    text += number(hi);
    text += "]";
    return text;
}

// Where the blob is and how it splits into block errors and payload.
std::string checkBlobExtent(const IndexContext& ctx, const std::string& name, const PatchRecord& r)
{
    const uint64_t begin = kHeaderSize, end = ctx.header.patchAreaEnd();
    if (r.offset < begin || r.offset > end || r.size > end - r.offset)
        return name + ": blob at offset " + std::to_string(r.offset) + ", size " +
               std::to_string(r.size) + " lies outside the patch area [" + std::to_string(begin) +
               ", " + std::to_string(end) + ")";
    if (r.block_errors_size != 0 && r.block_errors_size < kMinBlockErrorsSize)
        return name + ": block_errors_size is " + std::to_string(r.block_errors_size) +
               ": must be 0 (not stored) or >= " + std::to_string(kMinBlockErrorsSize) +
               " (an f32 quantum and a zstd frame)";
    if (r.block_errors_size >= r.size)
        return name + ": block_errors_size " + std::to_string(r.block_errors_size) +
               " leaves no payload in a blob of " + std::to_string(r.size) + " bytes";
    // Version 2 blobs carry a validity mask (at least its kind byte) before the payload,
    // version 4 blobs also the sample flags (likewise).
    const uint32_t masks = (ctx.header.version >= kFirstVersionWithValidity ? 1u : 0u) +
                           (ctx.header.version >= kFirstVersionWithSampleFlags ? 1u : 0u);
    if (r.size - r.block_errors_size < masks + 1)
        return name + ": block_errors_size " + std::to_string(r.block_errors_size) +
               " leaves no room for the masks (" + std::to_string(masks) +
               " bytes at least) and a payload in a blob of " + std::to_string(r.size) + " bytes";
    return {};
}

// min/max: finite, ordered, within the heights codes can take widened by δ_l (lossy codecs
// widen the bounds of what they decode by δ_l; the writer clamps to the code range, the
// widening is a reader's tolerance), rounded outwards to f32 as the writer rounds them.
std::string checkHeights(const IndexContext& ctx, const std::string& name, const PatchRecord& r,
                         double delta)
{
    if (!(r.min_height <= r.max_height))
        return name + ": min_height " + number(r.min_height) + " > max_height " +
               number(r.max_height);
    const Header& h = ctx.header;
    const float lowest = floatDown(h.height_offset - delta);
    const float highest = floatUp(h.height_offset + kMaxCode * h.height_scale + delta);
    for (const auto& [field, value] :
         {std::pair{"min_height", r.min_height}, std::pair{"max_height", r.max_height}})
        if (!(value >= lowest && value <= highest))
            return name + ": " + field + " is " + number(value) + ": must be a number in " +
                   range(lowest, highest) +
                   " (the heights of codes 0..65535 widened by δ_l = " + formatNumber(delta) + ")";
    return {};
}

// Err_Appr and Err (docs/FORMAT.md, "Error bounds"): Err_Appr is 0 at the finest level and at
// most one code range (65535 codes) per level below, since Err_Int compares codes with an
// interpolant of codes; Err = Err_Appr + δ_l rounded up, so it lies between
// max(Err_Appr, δ_l) and floatUp(Err_Appr + δ_l) (the writer adds the unrounded Err_Appr).
std::string checkErrors(const IndexContext& ctx, const std::string& name, const PatchRecord& r,
                        int level, double delta)
{
    const int levels_below = ctx.geometry.finestLevel() - level;
    if (levels_below == 0 && r.err_appr != 0)
        return name + ": err_appr is " + number(r.err_appr) + ": must be 0 at the finest level";
    // 1e-6 absorbs the f32 rounding of Err_Int sums.
    const float appr_max = floatUp(levels_below * kMaxCode * ctx.header.height_scale * (1 + 1e-6));
    if (!(r.err_appr >= 0 && r.err_appr <= appr_max))
        return name + ": err_appr is " + number(r.err_appr) + ": must be a number in " +
               range(0, appr_max) + " (at most 65535 codes for each of the " +
               std::to_string(levels_below) + " levels below)";
    const double err_lo = std::max(double(r.err_appr), delta);
    const double err_hi = floatUp(double(r.err_appr) + delta);
    if (!(r.err >= err_lo && r.err <= err_hi))
        return name + ": err is " + number(r.err) + ": must be a number in " +
               range(err_lo, err_hi) +
               " (Err = err_appr + δ_l rounded up, δ_l = " + formatNumber(delta) + ")";
    return {};
}

} // namespace

std::string checkIndexEntry(const IndexContext& ctx, int64_t i, const PatchRecord& r)
{
    const PatchId p = ctx.geometry.patchAt(i);
    if (r.level != static_cast<uint32_t>(p.level) || r.x != static_cast<uint32_t>(p.x) ||
        r.y != static_cast<uint32_t>(p.y))
        return "index entry " + std::to_string(i) + " is out of order: it says level " +
               std::to_string(r.level) + ", x " + std::to_string(r.x) + ", y " +
               std::to_string(r.y) + " but position " + std::to_string(i) + " holds " +
               ArchiveReader::patchName(p);
    const std::string name = entryName(i, p);
    if (std::string problem = checkBlobExtent(ctx, name, r); !problem.empty())
        return problem;
    for (const auto& [field, value] :
         {std::pair{"min_height", r.min_height}, std::pair{"max_height", r.max_height},
          std::pair{"err_appr", r.err_appr}, std::pair{"err", r.err}})
        if (!std::isfinite(value))
            return name + ": " + field + " is " + number(value) + ": must be a finite number";
    const double delta = ctx.level_bound[p.level];
    if (std::string problem = checkHeights(ctx, name, r, delta); !problem.empty())
        return problem;
    return checkErrors(ctx, name, r, p.level, delta);
}

std::string checkIndexHierarchy(const IndexContext& ctx, const std::vector<PatchRecord>& records)
{
    const PyramidGeometry& g = ctx.geometry;
    if (g.levelCount() < 2)
        return {};
    // Each child against its parent: by induction a bound covers every descendant.
    for (int64_t i = g.firstPatchIndex(1); i < g.patchCount(); ++i) {
        const PatchId child = g.patchAt(i);
        const int64_t pi = g.patchIndex(child.parent());
        const PatchRecord& P = records[static_cast<size_t>(pi)];
        const PatchRecord& C = records[static_cast<size_t>(i)];
        const std::string of_child = " of its child " + ArchiveReader::patchName(child);
        const std::string parent = entryName(pi, child.parent());
        if (P.min_height > C.min_height)
            return parent + ": min_height " + number(P.min_height) + " > min_height " +
                   number(C.min_height) + of_child + " (bounds cover every descendant)";
        if (P.max_height < C.max_height)
            return parent + ": max_height " + number(P.max_height) + " < max_height " +
                   number(C.max_height) + of_child + " (bounds cover every descendant)";
        if (P.err_appr < C.err_appr)
            return parent + ": err_appr " + number(P.err_appr) + " < err_appr " +
                   number(C.err_appr) + of_child +
                   " (Err_Appr(P) = Err_Int(P) + max over children)";
    }
    return {};
}

std::string checkBlobTiling(const IndexContext& ctx, const std::vector<PatchRecord>& records)
{
    std::vector<int64_t> order(records.size());
    std::iota(order.begin(), order.end(), int64_t{0});
    std::sort(order.begin(), order.end(),
              [&](int64_t a, int64_t b) { return records[a].offset < records[b].offset; });
    const PyramidGeometry& g = ctx.geometry;
    uint64_t covered = kHeaderSize; // every byte before this belongs to the header or a blob
    int64_t previous = -1;
    for (const int64_t k : order) {
        const PatchRecord& r = records[static_cast<size_t>(k)];
        if (r.offset < covered) // blobs are non-empty, so `previous` exists
            return entryName(k, g.patchAt(k)) + ": blob [" + std::to_string(r.offset) + ", " +
                   std::to_string(r.offset + r.size) + ") overlaps the blob of " +
                   ArchiveReader::patchName(g.patchAt(previous)) + ", which ends at " +
                   std::to_string(covered);
        if (r.offset > covered)
            return "index: bytes [" + std::to_string(covered) + ", " + std::to_string(r.offset) +
                   ") before the blob of " + ArchiveReader::patchName(g.patchAt(k)) +
                   " belong to no patch (blobs tile the patch area)";
        covered = r.offset + r.size;
        previous = k;
    }
    if (covered != ctx.header.patchAreaEnd())
        return "index: bytes [" + std::to_string(covered) + ", " +
               std::to_string(ctx.header.patchAreaEnd()) +
               ") after the last blob belong to no patch (blobs tile the patch area)";
    return {};
}

} // namespace ridge::archive
